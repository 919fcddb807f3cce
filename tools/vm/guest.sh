# shellcheck shell=bash
# Shared by tools/vm/run and tools/vm/session (sourced, not run): the prepared image's checks,
# the command script a guest runs, and QEMU's command line. The caller defines die() (exit 125).

# vm_check_image DIR: dies unless DIR/image holds a guest prepared by these tools/vm scripts;
# sets vm_image and vm_qemu.
vm_check_image() {
  local here
  here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
  vm_image=$1/image
  if [ ! -s "$vm_image/vmlinux" ] || [ ! -s "$vm_image/initrd.gz" ] || [ ! -f "$vm_image/key" ]; then
    die "no prepared guest image in '$vm_image' (run: tools/vm/prepare '$1')"
  fi
  local scripts_hash
  scripts_hash=$(cat "$here/prepare" "$here/init" "$here/gpio-sim-chip" | sha256sum | cut -c1-16)
  case "$(cat "$vm_image/key")" in
    *" $scripts_hash") ;;
    *) die "guest image in '$vm_image' was prepared by other tools/vm scripts (key '$(cat "$vm_image/key")'); run: tools/vm/prepare '$1'" ;;
  esac
  vm_qemu=$(command -v qemu-system-x86_64) || die "qemu-system-x86_64 not found; run tools/setup"
}

# vm_write_command FILE CMD [ARG...]: the script the guest runs: the caller's environment and
# directory, then exec the command.
vm_write_command() {
  local file=$1
  shift
  {
    echo "set +o posix"
    export -p | grep -Ev '^declare -x (PWD|OLDPWD|SHLVL|_)(=|$)'
    printf 'cd %q || exit 125\n' "$(pwd)"
    printf 'exec'; printf ' %q' "$@"; printf '\n'
  } > "$file"
}

# vm_qemu_args SHARE CONSOLE_LOG APPEND_EXTRA: sets the array vm_args, QEMU's arguments for a
# guest whose control share is SHARE (TCG: KVM does not work nested here, docs/vcan.md).
vm_qemu_args() {
  vm_args=(-accel tcg -cpu max -smp 2 -m 1024 -nodefaults -display none -no-reboot
           -serial "file:$2" -kernel "$vm_image/vmlinux" -initrd "$vm_image/initrd.gz"
           -append "console=ttyS0 quiet loglevel=3 panic=-1 tsc=reliable swum.ctl=$1${3:+ $3}"
           -virtfs "local,path=/,mount_tag=hostroot,security_model=passthrough,readonly=on,multidevs=remap"
           -virtfs "local,path=$1,mount_tag=ctl,security_model=none")
}
