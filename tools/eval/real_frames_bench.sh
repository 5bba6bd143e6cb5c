#!/usr/bin/env bash
# Real-frame benchmark (issue 30): what a user's own real frames give, on the labelled public
# frames a developer keeps beside the repository (a folder with a MANIFEST.tsv: path, source,
# path, commit, sensor, size, label kinds, key=value labels, notes). Prints:
#   heads      per labelled set (GelSight Mini billets: roughness, grouped by billet; Mini slip
#              episodes: slip, contact frames, grouped by object): the shipped head where one
#              answers the question, the head fitted on the set (grouped cross-validation), the
#              pixel baseline on the same folds, the majority rate, n, groups and 95 % intervals;
#              and how accuracy grows with the labelled groups per class (`--learning-curve`)
#   contact    the board's contact gate calibrated on each session's no-contact reference frame:
#              contact frames seen, no-contact frames (other than the reference) called contact
#   stability  embedding cosine under JPEG re-encoding and +-3 DN (`tlvlink stability --real`)
#   adapt      (with CHECKPOINT) the encoder's last conv layer adapted on each set vs the linear
#              head, on the same grouped folds (`tlvlink adapt`; needs the trainer build and the
#              checkpoint the shipped model came from: tools/setup/make_default_models.sh OUT
#              leaves it as OUT/tiny.ckpt, too large to ship)
# Every figure is on REAL frames; none is a simulator figure.
#   tools/eval/real_frames_bench.sh REAL_DIR [MODEL [CHECKPOINT [FP32_MODEL]]]
# Environment: TLVLINK_BUILD (default build/host).
set -euo pipefail
cd "$(dirname "$0")/../.."
real=${1:?usage: real_frames_bench.sh REAL_DIR [MODEL]}
model=${2:-firmware/models/touch-tiny-int8.tlvm}
checkpoint=${3:-}
fp32_model=${4:-firmware/models/touch-tiny-fp32.tlvm}
manifest=$real/MANIFEST.tsv
[ -f "$manifest" ] || { echo "real_frames_bench: $manifest absent: no real frames to measure" >&2; exit 2; }
tlvlink=${TLVLINK_BUILD:-build/host}/tools/cli/tlvlink
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# label KEY LABELS -> value ("" when absent)
label() { tr ';' '\n' <<< "$2" | sed -n "s/^$1=//p"; }

# ImageFolder layouts as a user makes them, of symlinks into REAL_DIR.
while IFS=$'\t' read -r path _ _ _ sensor _ _ labels _; do
  [ "$path" = local_path ] && continue
  rough=$(label roughness "$labels"); slip=$(label slip "$labels")
  object=$(label object "$labels"); inferred=$(label contact_inferred "$labels")
  name=$(tr '/' '_' <<< "$path")
  if [ -n "$rough" ]; then
    mkdir -p "$work/billets/$rough/$object"
    ln -s "$(realpath "$real/$path")" "$work/billets/$rough/$object/$name"
  fi
  if [ -n "$slip" ] && [ "$inferred" = yes ]; then
    mkdir -p "$work/slip/$slip"
    ln -s "$(realpath "$real/$path")" "$work/slip/$slip/$name"
    printf '%s/%s\t%s\n' "$slip" "$name" "$object" >> "$work/slip/groups.tsv"
  fi
done < "$manifest"

echo "== heads on real frames (model $model)"
echo "-- GelSight Mini billets, roughness (rough = unground, smooth = ground; groups: billets)"
"$tlvlink" eval "$model" --images "$work/billets" --head rough_smooth | sed 's/^/shipped rough_smooth: /'
"$tlvlink" heads fit "$model" --images "$work/billets" --head roughness --learning-curve \
  -o "$work/billets.tlvm"
echo "-- roughness fitted on two billets per class, scored on the third pair (recorded interval vs new billets)"
for held in $(ls "$work/billets/rough"); do
  n=${held#steel_}; n=${n%%_*}   # billet1, billet2, ...
  rm -rf "$work/fit" "$work/new"
  for cls in rough smooth; do
    mkdir -p "$work/fit/$cls" "$work/new/$cls"
    for g in "$work/billets/$cls"/*; do
      case "$(basename "$g")" in *"${n}_"*) cp -P -r "$g" "$work/new/$cls/" ;; *) cp -P -r "$g" "$work/fit/$cls/" ;; esac
    done
  done
  "$tlvlink" heads fit "$model" --images "$work/fit" --head rough_smooth -o "$work/held.tlvm" \
    --overwrite > /dev/null
  "$tlvlink" eval "$work/held.tlvm" --images "$work/new" --head rough_smooth |
    grep -E "accuracy|recorded|interval" | sed "s/^/  $n held out: /"
done
echo "-- GelSight Mini slip episodes, slip (contact frames; groups: objects; the shipped model has no slip head)"
"$tlvlink" heads fit "$model" --images "$work/slip" --head slip --learning-curve -o "$work/slip.tlvm"

if [ -n "$checkpoint" ]; then
  echo
  echo "== adapting the encoder on real frames vs the linear head (fp32 $fp32_model, checkpoint $checkpoint)"
  for set in billets:roughness slip:slip; do
    for layers in 1 2; do
      echo "-- ${set%%:*}, last $layers conv layer(s) + FC"
      "$tlvlink" adapt "$fp32_model" --checkpoint "$checkpoint" --images "$work/${set%%:*}" \
        --head "${set#*:}" --layers "$layers" --threads 2
    done
  done
fi

echo
echo "== contact gate on real frames (calibrated on each session's reference frame)"
# Sessions: frames of one folder with a no-contact reference (ref.*, frame_0.*, or the first
# contact=no frame); slip episodes: the pre-grasp frame is the reference, contact_inferred the label.
awk -F'\t' 'NR > 1 {
  n = split($1, parts, "/"); dir = $1; sub("/[^/]*$", "", dir); file = parts[n]
  c = ""; m = split($8, kv, ";")
  for (i = 1; i <= m; ++i) { split(kv[i], p, "="); if (p[1] == "contact" || p[1] == "contact_inferred") c = p[2] }
  if (c == "") next
  print dir "\t" file "\t" c
}' "$manifest" | sort > "$work/contact.tsv"
gate_on_sessions() {  # FLOOR_DN [verbose]
  local verbose=${2:-0}
  local seen=0 events=0 false_contacts=0 idle=0 dir rows ref threshold result s_seen s_events s_false s_idle f truth said
  while IFS= read -r dir; do
    rows=$(awk -F'\t' -v d="$dir" '$1 == d' "$work/contact.tsv")
    ref=$(awk -F'\t' '$3 == "no" && ($2 ~ /^ref\./ || $2 ~ /^frame_0\./) {print $2; exit}' <<< "$rows")
    [ -z "$ref" ] && ref=$(awk -F'\t' '$3 == "no" {print $2}' <<< "$rows" | sort -V | head -n 1)
    [ -z "$ref" ] && continue
    mapfile -t others < <(awk -F'\t' -v r="$ref" '$2 != r && ($3 == "yes" || $3 == "no") {print $2}' <<< "$rows")
    [ ${#others[@]} -eq 0 ] && continue
    args=(); for f in "${others[@]}"; do args+=("$real/$dir/$f"); done
    result=$("$tlvlink" contact --min-threshold "$1" -r "$real/$dir/$ref" "${args[@]}")
    threshold=$(sed -n 's/.*contact above \([0-9.]*\) DN.*/\1/p' <<< "$result")
    s_seen=0; s_events=0; s_false=0; s_idle=0
    for f in "${others[@]}"; do
      truth=$(awk -F'\t' -v f="$f" '$2 == f {print $3}' <<< "$rows")
      said=$(grep -F "$real/$dir/$f" <<< "$result" | awk '{print $1}')
      if [ "$truth" = yes ]; then
        s_events=$((s_events + 1)); [ "$said" = contact ] && s_seen=$((s_seen + 1))
      else
        s_idle=$((s_idle + 1)); [ "$said" = contact ] && s_false=$((s_false + 1))
      fi
    done
    [ "$verbose" = 1 ] && printf '  %-90s ref %-12s threshold %5s DN  contact seen %2d/%-2d  false %d/%d\n' \
      "$dir" "$ref" "$threshold" $s_seen $s_events $s_false $s_idle
    seen=$((seen + s_seen)); events=$((events + s_events))
    false_contacts=$((false_contacts + s_false)); idle=$((idle + s_idle))
    grep -E "^(contact|none) " <<< "$result" >> "$work/scores-$1.txt"
  done < <(cut -f1 "$work/contact.tsv" | uniq)
  [ "$verbose" = 1 ] && awk '$3 > 0 {print $3}' "$work/scores-$1.txt" | sort -n | head -n 5 | tr '\n' ' ' | sed 's/^/lowest scores of non-reference frames (DN): /; s/$/\n/'
  echo "contact gate, floor $1 DN: $seen of $events contact frames seen; $false_contacts of $idle no-contact frames (other than the reference) called contact"
}
gate_on_sessions 4 1   # the daemon's default floor (min_threshold_dn); one still as reference: no noise measured
# A floor between the no-contact and contact scores seen above, chosen on THESE frames (2
# no-contact frames only): a sensitivity row, to be checked on frames kept aside.
gate_on_sessions 12
echo
echo "== embedding stability on real frames"
"$tlvlink" stability "$model" --scenes 0 --real "$real" | grep -E "^real|^stability|targets"
