#!/bin/bash
# ctest install_and_run: `cmake --install` into a temporary prefix, then the installed rasm runs
# from another folder with its own libraries and the simulator's data installed beside it.
# usage: install_and_run.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" > /dev/null
mkdir "$prefix/elsewhere" && cd "$prefix/elsewhere"
rasm=$prefix/bin/rasm
fail() { echo "install_and_run: $*" >&2; exit 1; }
[[ -x $rasm ]] || fail "no $rasm after cmake --install"
core=$(ldd "$rasm" | awk '/librasm_core.so/ {print $3}')
[[ -n $core && $(realpath "$core") == "$prefix"/lib*/rasm/librasm_core.so ]] ||
  fail "the installed rasm does not load its own libraries: $(ldd "$rasm" | grep librasm_core)"
"$rasm" --version > /dev/null || fail "rasm --version failed"
# A rawlog given by path, mapped from another folder.
"$rasm" run "$src/rawlogs/sim_office_handheld_320x240.rawlog" --max-frames 3 --out run1 > /dev/null 2>&1 ||
  fail "run on the shipped rawlog failed"
grep -q '"status": "ok"' run1/report.json || fail "run1/report.json is not ok"
# The simulator's data is the installed copy: a missing trajectory spec names that folder ...
if out=$("$rasm" run --set sim.trajectory=no_such_spec --out run2 2>&1); then fail "no_such_spec ran"; fi
grep -q "$prefix/share/rasm/sim/trajectories" <<< "$out" ||
  fail "the error does not name the installed sim data: $out"
# ... and the embedded default (the simulated office) runs from it.
"$rasm" run --max-frames 3 --out run3 > /dev/null 2>&1 || fail "the embedded default failed"
grep -q '"status": "ok"' run3/report.json || fail "run3/report.json is not ok"
[[ -f $prefix/share/rasm/ini/default.ini && -f $prefix/share/doc/rasm/README.md ]] ||
  fail "the INIs or the docs were not installed"
[[ -s $prefix/share/man/man1/rasm.1 && -s $prefix/share/bash-completion/completions/rasm ]] ||
  fail "the man page or the bash completion was not installed"
echo "install_and_run: ok ($prefix)"
