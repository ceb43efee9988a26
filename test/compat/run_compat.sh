#!/usr/bin/env bash
# `make test-compat`: builds the package and runs its whole ctest suite on an older toolchain,
# Debian 11 (bullseye: gcc 10, PCL 1.11, Python 3.9, catkin 0.8.9), the closest to ROS Noetic
# robots that Debian's archive offers; then checks with vermin that the Python code needs
# nothing newer than Python 3.8 (Noetic's Ubuntu 20.04).
#
# The chroot is made with debootstrap into .compat/ (git-ignored, ~4 GB) and reused when it is
# already there. The repository's working tree (tracked and untracked, not ignored files) is
# copied into a catkin workspace inside the chroot, so the host's .ws is never touched.
# Needs root (debootstrap, mount, chroot); uses sudo when not root.
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
compat_dir=$repo/.compat
root=$compat_dir/bullseye
venv=$compat_dir/venv
pkg=ohm_mirror_detector3d
# The Debian mirror comes from the machine's own apt configuration (the only archive these
# machines reach), never from a name written here: the first active `deb` line or deb822
# `URIs:` entry whose path ends in /debian. COMPAT_MIRROR overrides it. Comment lines are
# skipped (they may name other archives).
apt_sources=(/etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources)
mirror=${COMPAT_MIRROR:-$(cat "${apt_sources[@]}" 2>/dev/null | grep -E '^(URIs:|deb )' \
  | grep -o -E '[a-z]+://[^ ]+/debian/?( |$)' | tr -d ' ' | head -n1 || true)}
if [ -z "$mirror" ]; then
  echo "test-compat: no Debian mirror configured: looked for an active 'deb' or 'URIs:' entry ending in /debian" \
    "in ${apt_sources[*]}; configure apt (or set COMPAT_MIRROR) and run again" >&2
  exit 1
fi

sudo=
[ "$(id -u)" = 0 ] || sudo=sudo
start=$(date +%s)
log() { echo "[test-compat $(( $(date +%s) - start ))s] $*"; }

# --- 1. Python 3.8 syntax and library use (vermin, in a venv of Debian's python3) ---------
# First, so that it reports even when the chroot part fails.
if [ ! -x "$venv/bin/vermin" ]; then
  log "installing vermin into $venv"
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/pip" install -q vermin
fi
python_files=$(cd "$repo" && { echo setup.py; find src/$pkg test bench -name '*.py'; \
  grep -l -r -m1 '^#!.*python' scripts test bench cfg 2>/dev/null; } | sort -u)
log "vermin: $(echo "$python_files" | wc -l) Python files must run on Python 3.8"
# --eval-annotations: annotations are evaluated at run time on 3.8 (no PEP 563 by default).
# --no-tips: only violations, no advice about backports.
(cd "$repo" && "$venv/bin/vermin" -t=3.8- --violations --eval-annotations --no-tips $python_files)
log "vermin: OK"

# What neither vermin nor Debian 11 sees, but Ubuntu 20.04 (Noetic) would: PCL 1.10's Ptr is a
# boost::shared_ptr (std::make_shared of a PCL type does not convert to it) and has no
# pcl::Indices / pcl::index_t; Python 3.8 has no str.removeprefix/removesuffix (vermin cannot
# see method calls on untyped variables). Comment lines are skipped.
noetic_only=$(cd "$repo" && {
  grep -rnE 'make_shared<[[:space:]]*(pcl::|Cloud\b)|pcl::make_shared|pcl::Indices\b|pcl::index_t\b' \
    src include test bench --include='*.cpp' --include='*.h' || true
  grep -rnE '\.remove(prefix|suffix)\(' $python_files || true
} | grep -vE '^[^:]+:[0-9]+:[[:space:]]*(//|#)' || true)
if [ -n "$noetic_only" ]; then
  echo "$noetic_only"
  echo "these lines would not build or run on ROS Noetic (Ubuntu 20.04: PCL 1.10, Python 3.8)" >&2
  exit 1
fi
log "no PCL >= 1.11 or Python >= 3.9 only constructs (grep): OK"

# --- 2. The chroot ---------------------------------------------------------------------------
if [ ! -e "$root/.compat_bootstrapped" ]; then
  log "debootstrap bullseye into $root from $mirror"
  $sudo rm -rf "$root"
  $sudo debootstrap --variant=minbase bullseye "$root" "$mirror" > "$compat_dir/debootstrap.log" 2>&1 \
    || { tail -n 30 "$compat_dir/debootstrap.log"; exit 1; }
  # No bullseye-security: its index has missing files on this mirror.
  echo "deb $mirror bullseye main
deb $mirror bullseye-updates main" | $sudo tee "$root/etc/apt/sources.list" > /dev/null
  # A minbase chroot has no /etc/hosts, and rostest must resolve localhost.
  echo "127.0.0.1 localhost" | $sudo tee "$root/etc/hosts" > /dev/null
  $sudo touch "$root/.compat_bootstrapped"
fi

mounted=()
cleanup() {
  local status=$?
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
    $sudo umount "${mounted[i]}" || $sudo umount -l "${mounted[i]}" || true
  done
  exit $status
}
trap cleanup EXIT INT TERM
mount_in() {  # mount_in TARGET MOUNT_ARGS...
  local target=$1; shift
  mountpoint -q "$target" || { $sudo mount "$@" "$target"; mounted+=("$target"); }
}
mount_in "$root/proc" -t proc proc
# /dev/null, /dev/urandom and /dev/shm for the tests' processes.
mount_in "$root/dev" --bind /dev

# pip in the chroot (make test's pip-install test) reaches the package index the way the host's pip
# does: with the host's pip configuration files, its PIP_* variables and the certificate bundle they
# name (a TLS-intercepting proxy's certificate authority may be only in the host's bundle).
pip_env=()
for conf in /etc/pip.conf /etc/xdg/pip "$HOME/.config/pip/pip.conf" "$HOME/.pip/pip.conf"; do
  [ -e "$conf" ] || continue
  target=$root${conf/#$HOME//root}
  $sudo mkdir -p "$(dirname "$target")" && $sudo cp -r "$conf" "$(dirname "$target")/"
done
pip_cert=${PIP_CERT:-$(cat /etc/pip.conf /etc/xdg/pip/pip.conf "$HOME/.config/pip/pip.conf" 2>/dev/null \
  | sed -n 's/^[[:space:]]*cert[[:space:]]*=[[:space:]]*//p' | tail -n1 || true)}
while IFS= read -r variable; do
  [ -n "$variable" ] && [ "${variable%%=*}" != PIP_CERT ] && pip_env+=("$variable")
done < <(env | grep '^PIP_' || true)
if [ -n "$pip_cert" ] && [ -f "$pip_cert" ]; then
  # A new minbase chroot has no /etc/ssl yet (ca-certificates comes with the packages below).
  $sudo mkdir -p "$root/etc/ssl"
  $sudo cp "$pip_cert" "$root/etc/ssl/host-pip-certificates.pem"
  pip_env+=(PIP_CERT=/etc/ssl/host-pip-certificates.pem)
fi

in_chroot() {  # a clean environment: none of the host's pyenv or ROS variables
  $sudo chroot "$root" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM=dumb \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin "${pip_env[@]}" "$@"
}

# The same Debian packages as the host build (read from the Makefile, so they stay in sync).
packages=$(make -s -C "$repo" --no-print-directory print-apt-packages)
missing=$(in_chroot dpkg-query -W -f='${Status} ${Package}\n' $packages 2>&1 \
  | awk '!/^install ok installed/ {print $NF}' || true)
if [ -n "$missing" ]; then
  log "installing into the chroot:" $missing
  in_chroot apt-get update -qq
  in_chroot env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    $packages > "$compat_dir/apt.log" 2>&1 || { tail -n 30 "$compat_dir/apt.log"; exit 1; }
fi
log "toolchain: $(in_chroot gcc -dumpfullversion), PCL $(in_chroot dpkg-query -W -f='${Version}' libpcl-dev), $(in_chroot python3 --version), $(in_chroot cmake --version | head -n1)"

# --- 3. Build and test in a workspace inside the chroot -------------------------------------
ws=/compat_ws
$sudo mkdir -p "$root$ws/src/$pkg"
# A fresh copy of the working tree; tar keeps mtimes, so the kept build/ is incremental.
$sudo find "$root$ws/src/$pkg" -mindepth 1 -delete
(cd "$repo" && git ls-files -z --cached --others --exclude-standard \
  | xargs -0 -r sh -c 'for f; do [ -e "$f" ] && printf "%s\0" "$f"; done' sh \
  | tar --null -T - -cf -) | $sudo tar -xf - -C "$root$ws/src/$pkg"

# bullseye's catkin 0.8.9 cannot reconfigure a kept build/ whose tests changed: the second CMake run
# defines the gtest targets twice and asks for a `gmock_main` target that does not exist ("No rule
# to make target 'gmock_main'"). So build/ and devel/ are kept only while CMakeLists.txt and
# package.xml are unchanged; otherwise the build starts from scratch (a few minutes more).
stamp=$(cat "$repo/CMakeLists.txt" "$repo/package.xml" | sha1sum | cut -d' ' -f1)
if [ "$($sudo cat "$root$ws/.configured_from" 2>/dev/null)" != "$stamp" ]; then
  log "CMakeLists.txt or package.xml changed since the last build: building from scratch"
  $sudo rm -rf "$root$ws/build" "$root$ws/devel"
fi
build_in_chroot() {
  in_chroot /bin/bash -eo pipefail -c "
    export ROS_HOME=$ws/.ros ROS_LOG_DIR=$ws/.ros/log ROS_HOSTNAME=127.0.0.1
    mkdir -p $ws/devel/lib/python3/dist-packages \$ROS_LOG_DIR
    cd $ws
    nice -n 10 catkin_make all tests -j2 -DCMAKE_BUILD_TYPE=Release \
      -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON > build.log 2>&1
  "
}
log "building in the chroot (log: $root$ws/build.log)"
if ! build_in_chroot; then
  # The same catkin trouble also strikes a kept build whose CMakeLists.txt did not change, when
  # catkin_make decides to run CMake again: a build that fails on it is retried from scratch once.
  if $sudo grep -q "No rule to make target 'gmock_main'" "$root$ws/build.log" && [ -d "$root$ws/build" ]; then
    log "the kept build cannot be reconfigured (gmock_main): building from scratch"
    $sudo rm -rf "$root$ws/build" "$root$ws/devel"
    build_in_chroot || { $sudo tail -n 80 "$root$ws/build.log"; exit 1; }
  else
    $sudo tail -n 80 "$root$ws/build.log"
    exit 1
  fi
fi
$sudo grep -E 'warning:' "$root$ws/build.log" | sort -u | head -n 20 || true
echo "$stamp" | $sudo tee "$root$ws/.configured_from" > /dev/null
if [ "${COMPAT_RECORD_GOLDEN:-0}" = 1 ]; then
  # A change meant to alter the outputs re-records Debian 11's golden digests here (Debian 12's are
  # recorded on the host with golden.py record); the file comes back into the working tree.
  log "recording Debian 11's golden digests (COMPAT_RECORD_GOLDEN=1)"
  in_chroot /bin/bash -eo pipefail -c "
    export ROS_HOME=$ws/.ros ROS_LOG_DIR=$ws/.ros/log ROS_HOSTNAME=127.0.0.1
    source $ws/devel/setup.bash
    cd $ws/src/$pkg && python3 test/golden/golden.py record
  "
  $sudo cat "$root$ws/src/$pkg/test/golden/digests.json" > "$repo/test/golden/digests.json"
fi
log "running ctest in the chroot"
in_chroot /bin/bash -eo pipefail -c "
  export ROS_HOME=$ws/.ros ROS_LOG_DIR=$ws/.ros/log ROS_HOSTNAME=127.0.0.1
  source $ws/devel/setup.bash
  cd $ws/build && ctest -j2 --output-on-failure
"
log "test-compat passed (Debian 11 bullseye build + ctest, vermin 3.8)"
