#!/usr/bin/env bash
# `make package-check` (issue 22, README "Install without building"): checks the Debian package
# `make package` built, as installed: it is extracted with `dpkg-deb -x` into a fresh temporary
# root (removed afterwards) and everything runs from there, never from the build tree.
#   - the file name is Debian's napkin_<version>_<arch>.deb, and napkin --version names <version>;
#   - the files: napkin, the presets, the man page, the bash completion, the Python module (with its
#     type stubs and PEP 561 marker py.typed);
#   - napkin finds its presets in the package (<root>/usr/share/napkin/config), not in the source
#     tree it was built from; `napkin demo` writes its catalogue and report;
#   - the man page renders without warnings (man -l), the bash completion completes;
#   - `import napkin` loads the packaged module, and the pytest suite python/tests passes against
#     the packaged napkin and module;
#   - Depends names the runtime libraries (TBB, SQLite, spdlog/fmt, libzip; dpkg-shlibdeps);
#   - lintian reports no errors (E:);
#   - the systemd unit napkin-serve.service passes `systemd-analyze verify` (its ExecStart pointed
#     at the packaged napkin), and /etc/default/napkin is a conffile;
#   - the completion completes file names with spaces and --option=value;
#   - dpkg installs it into a private root (never /) and purges it without leaving a file behind,
#     although python3 wrote bytecode beside the module in between.
# Usage: package_check.sh <build dir of `make package`>
set -euo pipefail
build_dir=$1
source_dir=$(cd "$(dirname "$0")/.." && pwd)
fail() { echo "napkin package-check: $*" >&2; exit 1; }
step() { echo "napkin package-check: $*"; }

shopt -s nullglob
debs=("$build_dir"/napkin_*.deb)
[ ${#debs[@]} = 1 ] || fail "expected one napkin_*.deb in $build_dir (run make package), found ${#debs[@]}."
deb=$(realpath "${debs[0]}")  # absolute: the checks below run in a temporary folder
version=$(dpkg-deb -f "$deb" Version)
arch=$(dpkg-deb -f "$deb" Architecture)
[ "$arch" = "$(dpkg --print-architecture)" ] || fail "$deb is for $arch, not this machine's $(dpkg --print-architecture)."
[ "$(basename "$deb")" = "napkin_${version}_${arch}.deb" ] ||
  fail "$deb is not named napkin_${version}_${arch}.deb as Debian names packages."
step "$deb ($(du -k "$deb" | cut -f1) KiB): version $version, $arch"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
root=$work/root
dpkg-deb -x "$deb" "$root"
napkin=$root/usr/bin/napkin
site=$root/usr/lib/python3/dist-packages
for file in usr/bin/napkin usr/share/napkin/config/arrays/denton-3222.json \
    usr/share/napkin/config/processing/default.json usr/share/man/man1/napkin.1.gz \
    usr/share/bash-completion/completions/napkin usr/lib/python3/dist-packages/napkin/__init__.py \
    usr/lib/python3/dist-packages/napkin/__init__.pyi usr/lib/python3/dist-packages/napkin/_napkin.pyi \
    usr/lib/python3/dist-packages/napkin/py.typed lib/systemd/system/napkin-serve.service etc/default/napkin; do
  [ -f "$root/$file" ] || fail "the package has no /$file."
done
python_extension=("$site"/napkin/_napkin*.so "$site"/_napkin*.so)
[ ${#python_extension[@]} = 1 ] || fail "the package has ${#python_extension[@]} Python extensions _napkin*.so under /usr/lib/python3/dist-packages, not one."

# Depends: computed by dpkg-shlibdeps from the ELF files, so it names the libraries napkin links.
depends=$(dpkg-deb -f "$deb" Depends)
step "Depends: $depends"
missing=""
for library in 'libtbb' 'libsqlite3' 'libspdlog|libfmt' 'libzip' 'python3-numpy'; do
  grep -qE "(^|[ ,])($library)" <<< "$depends" || missing="${missing:+$missing, }${library//|/ or }"
done
[ -z "$missing" ] || fail "Depends of $deb does not name $missing."

# lintian, Debian's package checker: no errors (E:). The warnings that remain, and why, are in
# packaging/README.md. --fail-on none: its exit status then says only whether lintian itself ran.
step "lintian $deb"
lintian_output=$(lintian --fail-on none --tag-display-limit 0 "$deb" 2>&1) ||
  fail "lintian could not check $deb: $lintian_output"
[ -z "$lintian_output" ] || echo "$lintian_output"
! grep -q '^E: ' <<< "$lintian_output" || fail "lintian reports errors (E:) on $deb (above)."

# The systemd unit: systemd's own checker, with the unit's commands pointed at the packaged napkin
# (it checks that they are executable); any complaint fails, a warning included.
step "systemd-analyze verify napkin-serve.service"
mkdir -p "$work/unit"
sed "s|/usr/bin/napkin|$napkin|g" "$root/lib/systemd/system/napkin-serve.service" > "$work/unit/napkin-serve.service"
verify_output=$(systemd-analyze verify --man=no "$work/unit/napkin-serve.service" 2>&1) ||
  fail "systemd-analyze verify rejects napkin-serve.service: $verify_output"
[ -z "$verify_output" ] || fail "systemd-analyze verify warns about napkin-serve.service: $verify_output"
dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles | grep -qx /etc/default/napkin ||
  fail "/etc/default/napkin is not a conffile of $deb."

cd "$work"  # nothing below may pick up the source or build tree by accident
unset NAPKIN_CONFIG_DIR
step "napkin --version"
napkin_version=$("$napkin" --version)
[[ $napkin_version == "napkin $version+"* ]] || fail "napkin --version says \"$napkin_version\", not version $version."

# An unknown preset's error names the folder napkin looked in: the packaged one.
step "napkin's presets are the packaged ones"
printf 't\n0\n' > unknown_preset.csv
preset_error=$("$napkin" transform --array no-such-preset --out unknown_preset_out.csv unknown_preset.csv 2>&1) && \
  fail "napkin transform --array no-such-preset succeeded."
[[ $preset_error == *"a preset in $root/usr/share/napkin/config/arrays "* ]] ||
  fail "napkin does not look for its presets in the package's /usr/share/napkin/config: $preset_error"

step "napkin demo --out $work/demo"
"$napkin" demo --out "$work/demo" > demo.log 2>&1 || { cat demo.log; fail "napkin demo failed (its output above)."; }
[ -s "$work/demo/report.html" ] || fail "napkin demo wrote no report.html in $work/demo."
tests=$("$napkin" --db "$work/demo/napkin.db" query tests --format csv | tail -n +2 | wc -l)
[ "$tests" -gt 0 ] || fail "the demo catalogue $work/demo/napkin.db has no tests."
step "demo: report.html and a catalogue of $tests tests"

step "man -l usr/share/man/man1/napkin.1.gz"
man_warnings=$(LC_ALL=C.UTF-8 MANWIDTH=80 man --warnings -l "$root/usr/share/man/man1/napkin.1.gz" 2>&1 >man.txt) ||
  fail "man cannot render napkin.1.gz: $man_warnings"
[ -z "$man_warnings" ] || fail "napkin.1.gz renders with warnings: $man_warnings"
grep -q "napkin transform" man.txt || fail "the man page has no section on napkin transform."

step "bash completion"
completion=$(PATH="$root/usr/bin:$PATH" bash -c '
  . "$1"
  complete_line() { COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); COMPREPLY=(); _napkin; echo "${COMPREPLY[*]}"; }
  complete_line napkin tran; complete_line napkin transform --arr; complete_line napkin transform --array denton
' bash "$root/usr/share/bash-completion/completions/napkin")
[ "$completion" = $'transform\n--array\ndenton-3222' ] ||
  fail "the bash completion completes \"napkin tran\", \"napkin transform --arr\", \"--array denton\" as \"${completion//$'\n'/ | }\"."
# The words as bash hands them over (COMP_WORDBREAKS holds "="): "--format=" is "--format" "=", and
# "--format=c" is "--format" "=" "c". A file name with a space is one completion, whether the word
# typed so far is plain, escaped or quoted. Each COMPREPLY is printed as its elements between [].
touch "my data.csv"
completion=$(PATH="$root/usr/bin:$PATH" bash -c '
  . "$1"
  complete_line() {
    COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); COMPREPLY=(); _napkin
    printf "[%s]" "${COMPREPLY[@]}"; echo
  }
  complete_line napkin query tests --format =; complete_line napkin query tests --format = c
  complete_line napkin transform --array denton-3222 my; complete_line napkin transform --array denton-3222 "my\ d"
  complete_line napkin transform --array denton-3222 "\"my d"; complete_line napkin transform --out = my
' bash "$root/usr/share/bash-completion/completions/napkin")
expected=$'[table][csv][json]\n[csv]\n[my data.csv]\n[my data.csv]\n[my data.csv]\n[my data.csv]'
[ "$completion" = "$expected" ] ||
  fail "the bash completion completes \"query tests --format=\", \"--format=c\", \"transform ... my\", \"my\\ d\", \"\\\"my d\", \"--out=my\" as \"${completion//$'\n'/ | }\", not \"${expected//$'\n'/ | }\"."

# Debian's interpreter, the one the package's module is for (Depends: python3), whatever comes first in PATH.
python=/usr/bin/python3
step "import napkin"
module=$(PYTHONPATH=$site "$python" -c 'import napkin; print(napkin.__file__)')
[[ $module == "$site/"* ]] || fail "import napkin loaded $module, not the packaged module under $site."

step "pytest python/tests against the package"
# The NHTSA recordings where CTest finds them (python/CMakeLists.txt); those tests skip without.
NAPKIN_BIN=$napkin PYTHONPATH=$site NAPKIN_NHTSA_FRONTAL_DIR=${NAPKIN_NHTSA_FRONTAL_DIR:-$source_dir/../shared/data/nhtsa-frontal} \
  "$python" -m pytest -q -p no:cacheprovider "$source_dir/python/tests" ||
  fail "the pytest suite python/tests fails against the package (above)."
# Install and purge with dpkg itself, into a private root under $work (dpkg --root: its own
# database; the maintainer scripts run outside a chroot with DPKG_ROOT set), never into /.
# Between the two, python3 imports the module as root would: it writes __pycache__ beside it,
# which the package's prerm must remove for the purge to leave nothing behind.
step "dpkg --install, import napkin, dpkg --purge in $work/dpkg-root"
dpkg_root=$work/dpkg-root
mkdir -p "$dpkg_root/var/lib/dpkg/info" "$dpkg_root/var/lib/dpkg/updates"
touch "$dpkg_root/var/lib/dpkg/status"
private_dpkg=(dpkg --root="$dpkg_root" --force-script-chrootless --force-depends --force-not-root --log=/dev/null)
"${private_dpkg[@]}" --install "$deb" > dpkg-install.log 2>&1 ||
  { cat dpkg-install.log; fail "dpkg --install $deb into $dpkg_root failed (its output above)."; }
# (PYTHONDONTWRITEBYTECODE, if the caller's environment sets it, would keep python3 from writing.)
env -u PYTHONDONTWRITEBYTECODE PYTHONPATH="$dpkg_root/usr/lib/python3/dist-packages" "$python" -c 'import napkin'
[ -d "$dpkg_root/usr/lib/python3/dist-packages/napkin/__pycache__" ] ||
  fail "import napkin wrote no __pycache__ into $dpkg_root/usr/lib/python3/dist-packages/napkin: the purge below would prove nothing."
"${private_dpkg[@]}" --purge napkin > dpkg-purge.log 2>&1 ||
  { cat dpkg-purge.log; fail "dpkg --purge napkin in $dpkg_root failed (its output above)."; }
! grep -i 'warning' dpkg-purge.log || fail "dpkg --purge napkin warns (above)."
left=$(find "$dpkg_root" -path "$dpkg_root/var/lib/dpkg" -prune -o -type f -print)
[ -z "$left" ] || fail "dpkg --purge napkin left files behind: $left"

step "ok: $deb"
