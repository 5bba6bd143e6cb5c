#!/bin/sh
# USB gadget for the tlvlink stream on the board (configfs + FunctionFS, optionally CDC-ACM).
#   usb_gadget.sh setup [options]   create the gadget and mount functionfs (does not bind)
#   usb_gadget.sh bind  [--udc NAME] bind once the daemon has written its descriptors
#   usb_gadget.sh watch [--udc NAME] bind again whenever the gadget is unbound and ready (daemon restarts)
#   usb_gadget.sh unbind | teardown | status
# Options for setup (defaults in brackets):
#   --name NAME       gadget and functionfs instance name [tlvlink]
#   --vid 0xVVVV      idVendor  [0x1d6b, Linux Foundation: development only]
#   --pid 0xPPPP      idProduct [0x0104, Multifunction Composite Gadget]
#   --serial S        USB serial number [/etc/machine-id, first 16 characters]
#   --no-ffs          leave out the FunctionFS bulk function
#   --acm             add a CDC-ACM serial function (/dev/ttyGS0 here, /dev/ttyACM0 on the host)
#   --user U          owner of the functionfs mount, the user tlvlinkd runs as [root]
# Order: setup (root) -> start tlvlinkd with output "usb" (it writes the descriptors to ep0)
# -> bind (root). tlvlinkd can bind by itself when it may write the UDC file (output
# "usb:/dev/ffs-tlvlink,udc=NAME,gadget=/sys/kernel/config/usb_gadget/tlvlink"). A gadget with only
# --acm can be bound right after setup. POSIX sh + busybox: runs in the emulated board's initramfs.
set -eu

cmd=${1:-help}
[ $# -gt 0 ] && shift
name=tlvlink vid=0x1d6b pid=0x0104 serial="" ffs=1 acm=0 user=root udc=""
while [ $# -gt 0 ]; do
  case "$1" in
    --name) name=$2; shift 2 ;;
    --vid) vid=$2; shift 2 ;;
    --pid) pid=$2; shift 2 ;;
    --serial) serial=$2; shift 2 ;;
    --no-ffs) ffs=0; shift ;;
    --acm) acm=1; shift ;;
    --user) user=$2; shift 2 ;;
    --udc) udc=$2; shift 2 ;;
    *) echo "usb_gadget.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done

configfs=/sys/kernel/config
gadget=$configfs/usb_gadget/$name
ffs_dir=/dev/ffs-$name

die() { echo "usb_gadget.sh: $*" >&2; exit 1; }
first_udc() { for u in /sys/class/udc/*; do [ -e "$u" ] && { basename "$u"; return; }; done; }

setup() {
  [ "$(id -u)" = 0 ] || die "setup needs root (configfs, mount)"
  modprobe libcomposite 2>/dev/null || true
  [ -d $configfs/usb_gadget ] || mount -t configfs none $configfs || die "cannot mount configfs"
  [ -d $configfs/usb_gadget ] || die "no usb_gadget in configfs: kernel without CONFIG_USB_CONFIGFS (modprobe libcomposite)"
  [ -d "$gadget" ] && die "$gadget exists (run teardown first)"
  [ -n "$serial" ] || serial=$(cut -c1-16 /etc/machine-id 2>/dev/null || echo 0000000000000000)
  mkdir -p "$gadget"
  echo "$vid" > "$gadget/idVendor"
  echo "$pid" > "$gadget/idProduct"
  echo 0x0200 > "$gadget/bcdUSB"
  mkdir -p "$gadget/strings/0x409"
  echo tlvlink > "$gadget/strings/0x409/manufacturer"
  echo "tlvlink touch board" > "$gadget/strings/0x409/product"
  echo "$serial" > "$gadget/strings/0x409/serialnumber"
  mkdir -p "$gadget/configs/c.1/strings/0x409"
  echo "tlvlink stream" > "$gadget/configs/c.1/strings/0x409/configuration"
  echo 250 > "$gadget/configs/c.1/MaxPower"
  if [ "$acm" = 1 ]; then
    mkdir -p "$gadget/functions/acm.usb0"
    ln -s "$gadget/functions/acm.usb0" "$gadget/configs/c.1/"
  fi
  if [ "$ffs" = 1 ]; then
    modprobe usb_f_fs 2>/dev/null || true
    mkdir -p "$gadget/functions/ffs.$name"
    ln -s "$gadget/functions/ffs.$name" "$gadget/configs/c.1/"
    mkdir -p "$ffs_dir"
    # root needs no look-up (a minimal board's initramfs may have no /etc/passwd).
    if [ "$user" = root ]; then uid=0 gid=0
    else uid=$(id -u "$user") && gid=$(id -g "$user") || die "unknown user '$user'"; fi
    mount -t functionfs -o "uid=$uid,gid=$gid" "$name" "$ffs_dir" || die "cannot mount functionfs at $ffs_dir"
  fi
  where=""
  [ "$ffs" = 1 ] && where="; functionfs at $ffs_dir, bind after tlvlinkd starts"
  echo "usb_gadget.sh: gadget $name ($vid:$pid, serial $serial) ready$where"
}

ffs_ready() { [ "$ffs" = 0 ] || [ -e "$ffs_dir/ep1" ]; }

bind() {
  [ -n "$udc" ] || udc=$(first_udc)
  [ -n "$udc" ] || die "no USB device controller in /sys/class/udc (on the emulated board: modprobe dummy_hcd)"
  i=0
  until ffs_ready; do
    i=$((i + 1))
    [ $i -le 100 ] || die "$ffs_dir/ep1 did not appear in 10 s: is tlvlinkd running with output \"usb\"?"
    sleep 0.1
  done
  if [ -n "$(cat "$gadget/UDC" 2>/dev/null)" ]; then return 0; fi
  echo "$udc" > "$gadget/UDC" || die "binding to $udc failed"
  echo "usb_gadget.sh: $name bound to $udc"
}

case "$cmd" in
  setup) setup ;;
  bind) bind ;;
  watch)
    # The function vanishes when tlvlinkd closes ep0 (restart): bind again once it is back.
    while :; do
      if [ -z "$(cat "$gadget/UDC" 2>/dev/null)" ] && ffs_ready; then bind || true; fi
      sleep 0.5
    done ;;
  unbind) [ -e "$gadget/UDC" ] && echo "" > "$gadget/UDC" ;;
  teardown)
    [ -d "$gadget" ] || exit 0
    echo "" > "$gadget/UDC" 2>/dev/null || true
    mountpoint -q "$ffs_dir" 2>/dev/null && umount "$ffs_dir"
    for f in "$gadget"/configs/c.1/*.*; do [ -L "$f" ] && rm "$f"; done
    rmdir "$gadget"/configs/c.1/strings/0x409 "$gadget"/configs/c.1 2>/dev/null || true
    for f in "$gadget"/functions/*; do [ -d "$f" ] && rmdir "$f"; done
    rmdir "$gadget/strings/0x409" "$gadget" 2>/dev/null || true ;;
  status)
    [ -d "$gadget" ] || { echo "$name: not set up"; exit 1; }
    echo "$name: $(cat "$gadget/idVendor"):$(cat "$gadget/idProduct") bound to '$(cat "$gadget/UDC")'"
    ls "$gadget/configs/c.1" ;;
  help|-h|--help) sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//' ;;
  *) echo "usb_gadget.sh: unknown command '$cmd' (setup bind watch unbind teardown status)" >&2; exit 2 ;;
esac
