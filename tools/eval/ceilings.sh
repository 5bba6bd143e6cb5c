#!/usr/bin/env bash
# The ceilings table of firmware/models/README.md: the shipped model (fp32, int8) beside the
# task oracles and the supervised upper bounds, with and without curriculum, on its own sets, on
# sets of unseen sensor instances and on DIGIT sets.
#   tools/eval/ceilings.sh [OUT_DIR]     (OUT_DIR: /tmp/tlvlink-default, as make_default_models.sh)
# Run tools/setup/make_default_models.sh OUT_DIR first: this reuses its sets and models. Then:
# 1. the supervised upper bounds, trained on the same set with the same budget (12 epochs):
#    `tiny` (same size as the shipped student) and `small` (4x the parameters, 3x the MACs),
#    objective supervised (cross-entropy on the simulator's labels; tools/trainer/README.md);
# 2. the curriculum ablation: the shipped recipe with --no-curriculum, and the pure TLV-Link
#    objective (no supervised term) with and without the curriculum;
# 3. each gets heads fitted on the shipped model's heads' sets (`heads fit`), so every row
#    follows one protocol;
# 4. the unseen-sensor sets (GelSight Mini, 16 instances of other seeds) and the DIGIT sets;
# 5. `tlvlink eval` tables -> OUT_DIR/ceilings/*.txt.
# Five trainings of 5-15 min each on the shared 2-core machine, plus the sets and evals.
# A model already at its place is reused (not retrained).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-/tmp/tlvlink-default}
build=${TLVLINK_BUILD:-build/host}
tlvlink=$build/tools/cli/tlvlink
c=$out/ceilings
mkdir -p "$c"
for f in touch-tiny-fp32.tlvm touch-tiny-int8.tlvm heads-touch feel data; do
  [ -e "$out/$f" ] || { echo "ceilings: $out/$f missing; run make_default_models.sh $out" >&2; exit 1; }
done

train() {  # name objective arch [--no-curriculum]
  env TLVLINK_BUILD="$build" TLVLINK_TRAIN_NAME="$1" TLVLINK_TRAIN_OBJECTIVE="$2" \
    TLVLINK_TRAIN_ARCH="$3" bash tools/trainer/train_default.sh ${4:-} "$out"
}
fit() {  # model.tlvm -> heads.tlvm
  "$tlvlink" heads fit "$1" --touch "$out/heads-touch" --grasp "$out/feel" -q --overwrite -o "$2" > /dev/null
}
# name | objective | arch | extra train flags: trained into $out/NAME.tlvm unless it is there
# (the shipped recipe's ablation trains into $out/no-curriculum/tiny.tlvm, train_default.sh's
# place for it), then given heads on the shipped model's heads' sets.
models=(
  "sup-tiny|supervised|tiny|"
  "sup-small|supervised|small|"
  "tlv-link-only|tlv-link|tiny|"
  "tlv-link-only-nc|tlv-link|tiny|--no-curriculum"
  "no-curriculum|tlv-link+supervised|tiny|--no-curriculum"
)
for m in "${models[@]}"; do
  IFS='|' read -r name objective arch extra <<< "$m"
  src=$out/$name.tlvm
  [ "$name" = no-curriculum ] && src=$out/no-curriculum/tiny.tlvm
  [ "$name" = tlv-link-only-nc ] && src=$out/no-curriculum/tlv-link-only.tlvm
  if [ ! -f "$src" ]; then
    tname=$name; [ "$name" = no-curriculum ] && tname=tiny
    [ "$name" = tlv-link-only-nc ] && tname=tlv-link-only
    train "$tname" "$objective" "$arch" $extra
  fi
  [ -f "$c/$name.tlvm" ] || fit "$src" "$c/$name.tlvm"
done
for m in no-curriculum tlv-link-only tlv-link-only-nc; do
  [ -f "$c/$m-int8.tlvm" ] || "$tlvlink" quantize "$c/$m.tlvm" --calib "$out/data" --calib-split train \
    --keep-float first,last -o "$c/$m-int8.tlvm" -q > /dev/null
done

# Unseen sensor instances (other seeds; most of each set is test split) and DIGIT.
gen_touch() {  # dir seed sensor
  [ -f "$1/tlvlink_sim.json" ] || "$tlvlink" sim touch100k -o "$1" --sessions 600 \
    --frames-per-session 4 --seed "$2" --sensor "$3" --sensor-instances 16 --test-fraction 0.9 \
    --markers-fraction 0.5 --threads 2 --vision-height 24 --vision-width 32
}
gen_feel() {  # dir seed sensor
  [ -f "$1/tlvlink_sim.json" ] || "$tlvlink" sim feel -o "$1" --objects 250 --grasps-per-object 8 \
    --repacked --seed "$2" --sensor "$3" --sensor-instances 16 --test-fraction 0.9 \
    --vision-height 24 --vision-width 32 --threads 2
}
gen_touch "$out/unseen-touch" 77 gelsight-mini
gen_feel "$out/unseen-feel" 99 gelsight-mini
gen_touch "$out/digit-touch" 78 digit
gen_feel "$out/digit-feel" 98 digit

bounds=(--bound "supervised tiny (same size)=$c/sup-tiny.tlvm"
        --bound "supervised small (4x params)=$c/sup-small.tlvm")
for set in own:data:feel unseen:unseen-touch:unseen-feel digit:digit-touch:digit-feel; do
  IFS=: read -r name touch grasp <<< "$set"
  data=(--touch "$out/$touch" --grasp "$out/$grasp" -q)
  echo "== $name: shipped fp32 vs int8, bounds -> $c/$name.txt"
  "$tlvlink" eval "$out/touch-tiny-fp32.tlvm" --compare "$out/touch-tiny-int8.tlvm" \
    "${data[@]}" "${bounds[@]}" | tee "$c/$name.txt"
  for m in no-curriculum tlv-link-only tlv-link-only-nc; do
    echo "== $name: $m fp32 vs int8 -> $c/$name-$m.txt"
    "$tlvlink" eval "$c/$m.tlvm" --compare "$c/$m-int8.tlvm" "${data[@]}" --no-paper \
      --oracle-samples 0 | tee "$c/$name-$m.txt"
  done
done
