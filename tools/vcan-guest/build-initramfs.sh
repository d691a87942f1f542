#!/usr/bin/env bash
# Builds the vcan test guest in a work folder of the build tree: a Debian kernel and its CAN
# modules, and an initramfs with busybox-static, iproute2's ip, can-utils and the project's
# binaries (with every library ldd lists). No root needed.
#   build-initramfs.sh --work DIR --stickslip PATH --test-binary PATH
# Writes DIR/vmlinuz (and DIR/vmlinux, the uncompressed kernel, when it has a PVH entry) and
# DIR/initramfs.cpio. Downloaded .debs are cached in DIR/debs, so a
# rerun fetches nothing. Packages that are installed are taken from the installed files;
# others are fetched with `apt-get download` and unpacked with `dpkg-deb -x`.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
work="" stickslip="" test_binary=""
while [ $# -gt 0 ]; do
  case "$1" in
    --work) work="$2"; shift 2 ;;
    --stickslip) stickslip="$2"; shift 2 ;;
    --test-binary) test_binary="$2"; shift 2 ;;
    *) echo "build-initramfs: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -n "$work" ] && [ -x "$stickslip" ] && [ -x "$test_binary" ] || {
  echo "usage: build-initramfs.sh --work DIR --stickslip PATH --test-binary PATH" >&2; exit 2; }

mkdir -p "$work/debs" "$work/pkgs"
work="$(cd "$work" && pwd)"
debs="$work/debs"

# apt-get download into the cache folder (quietly; a root download warns about _apt's sandbox).
fetch_deb() {
  local package="$1" found
  found="$(ls "$debs/${package}_"*.deb 2>/dev/null | head -n 1 || true)"
  if [ -z "$found" ]; then
    (cd "$debs" && timeout 300 apt-get download -q "$package" 2>&1 | grep -v "^W: Download is performed unsandboxed" >&2 || true)
    found="$(ls "$debs/${package}_"*.deb 2>/dev/null | head -n 1 || true)"
    [ -n "$found" ] || { echo "build-initramfs: could not download the Debian package $package" >&2; exit 1; }
  fi
  echo "$found"
}

# The root of a package's files: / when installed, else the unpacked .deb.
package_root() {
  local package="$1"
  if dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    echo /
    return
  fi
  local target="$work/pkgs/$package"
  if [ ! -e "$target/.unpacked" ]; then
    rm -rf "$target" && mkdir -p "$target"
    dpkg-deb -x "$(fetch_deb "$package")" "$target"
    touch "$target/.unpacked"
  fi
  echo "$target"
}

# --- the kernel: linux-image-amd64 names the current image package ---------------------------
kernel_deb="$(ls "$debs"/linux-image-[0-9]*-amd64_*.deb 2>/dev/null | head -n 1 || true)"
if [ -z "$kernel_deb" ]; then
  meta="$(fetch_deb linux-image-amd64)"
  image="$(dpkg-deb -f "$meta" Depends | tr ',' '\n' | sed -n 's/^ *\(linux-image-[0-9][^ ]*\).*/\1/p' | head -n 1)"
  [ -n "$image" ] || { echo "build-initramfs: linux-image-amd64 names no kernel image" >&2; exit 1; }
  kernel_deb="$(fetch_deb "$image")"
fi
kernel_dir="$work/kernel"
if [ ! -e "$kernel_dir/.stamp" ] || [ "$(cat "$kernel_dir/.stamp")" != "$(basename "$kernel_deb")" ]; then
  rm -rf "$kernel_dir" && mkdir -p "$kernel_dir"
  dpkg-deb --fsys-tarfile "$kernel_deb" | tar -x -C "$kernel_dir" --wildcards \
    './boot/vmlinuz-*' \
    './lib/modules/*/kernel/net/can/can.ko*' './lib/modules/*/kernel/net/can/can-raw.ko*' \
    './lib/modules/*/kernel/drivers/net/can/dev/can-dev.ko*' \
    './lib/modules/*/kernel/drivers/net/can/vcan.ko*' \
    './lib/modules/*/modules.order' './lib/modules/*/modules.builtin' \
    './lib/modules/*/modules.builtin.modinfo'
  basename "$kernel_deb" > "$kernel_dir/.stamp"
fi
kernel_version="$(ls "$kernel_dir/lib/modules" | head -n 1)"
cp "$kernel_dir/boot/vmlinuz-$kernel_version" "$work/vmlinuz"

# The uncompressed kernel (ELF) boots through its PVH entry point: qemu skips the firmware's
# real-mode set-up and the kernel's self-decompression, which take ~10 s under TCG. Found as in
# the kernel's scripts/extract-vmlinux: the first compressed stream inside the bzImage.
extract_vmlinux() {
  local bzimage="$1" target="$2" magic tool offset
  for pair in '\xFD\x37\x7A\x58\x5A\x00:xz -dc' '\x28\xB5\x2F\xFD:zstd -dcq' '\x1F\x8B\x08:gzip -dc'; do
    magic="${pair%%:*}" tool="${pair#*:}"
    for offset in $(LC_ALL=C grep -obUaP "$magic" "$bzimage" 2>/dev/null | cut -d: -f1 | head -n 3); do
      tail -c +$((offset + 1)) "$bzimage" | $tool > "$target.tmp" 2>/dev/null || true
      if [ "$(head -c 4 "$target.tmp" | od -An -c | tr -d ' ')" = '177ELF' ] &&
          readelf -n "$target.tmp" 2>/dev/null | grep -q '(0x00000012)'; then  # XEN_ELFNOTE_PHYS32_ENTRY
        mv "$target.tmp" "$target"
        return 0
      fi
    done
  done
  rm -f "$target.tmp"
  return 1
}
if [ ! -e "$kernel_dir/vmlinux" ] && [ ! -e "$kernel_dir/no-vmlinux" ]; then
  extract_vmlinux "$work/vmlinuz" "$kernel_dir/vmlinux" || touch "$kernel_dir/no-vmlinux"
fi
rm -f "$work/vmlinux"
[ -e "$kernel_dir/vmlinux" ] && ln -s "$kernel_dir/vmlinux" "$work/vmlinux"

# --- the root file system --------------------------------------------------------------------
root="$work/root"
rm -rf "$root"
mkdir -p "$root"/{bin,sbin,usr/bin,usr/sbin,usr/local/bin,proc,sys,dev,tmp,run,vcan,lib64}

# Copies a binary to usr/local/bin and every library ldd lists to the same path in the guest.
copy_with_libraries() {
  local binary="$1" name="${2:-$(basename "$1")}"
  cp -L "$binary" "$root/usr/local/bin/$name"
  local listing
  listing="$(ldd "$binary" 2>&1 || true)"
  if grep -q "not found" <<<"$listing"; then
    echo "build-initramfs: $binary needs libraries that are not installed:" >&2
    grep "not found" <<<"$listing" >&2
    exit 1
  fi
  local library
  for library in $(sed -n 's/.*=> \(\/[^ ]*\) (.*/\1/p; s/^[[:space:]]*\(\/[^ ]*\) (.*/\1/p' <<<"$listing"); do
    if [ ! -e "$root$library" ]; then
      mkdir -p "$root$(dirname "$library")"
      cp -L "$library" "$root$library"
    fi
  done
}

busybox_root="$(package_root busybox-static)"
cp "$busybox_root/bin/busybox" "$root/bin/busybox"
if ldd "$root/bin/busybox" >/dev/null 2>&1; then
  echo "build-initramfs: $busybox_root/bin/busybox is not static (install busybox-static)" >&2; exit 1
fi

iproute_root="$(package_root iproute2)"
copy_with_libraries "$iproute_root/bin/ip" ip
canutils_root="$(package_root can-utils)"
for tool in cangen candump canplayer cansend; do
  copy_with_libraries "$canutils_root/usr/bin/$tool"
done
copy_with_libraries "$stickslip" stickslip
copy_with_libraries "$test_binary" test_socketcan

mkdir -p "$root/lib/modules"
cp -a "$kernel_dir/lib/modules/$kernel_version" "$root/lib/modules/"
depmod -b "$root" "$kernel_version"

cp "$here/init" "$root/init"
cp "$here/guest-tests.sh" "$root/vcan/guest-tests.sh"
chmod +x "$root/init" "$root/vcan/guest-tests.sh"

# Uncompressed: the kernel unpacks it faster than it could inflate it under TCG.
(cd "$root" && find . -print | LC_ALL=C sort | cpio -o -H newc --quiet) > "$work/initramfs.cpio.tmp"
mv "$work/initramfs.cpio.tmp" "$work/initramfs.cpio"
echo "build-initramfs: kernel $kernel_version, initramfs $(du -k "$work/initramfs.cpio" | cut -f1) KiB" >&2
