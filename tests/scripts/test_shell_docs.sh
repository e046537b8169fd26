#!/bin/bash
# The man page and the bash completion the build generates (app/ShellDocs.h): the man page renders
# without warnings and documents every command; the completion completes commands, subcommands,
# options and --set keys of this binary. Usage: test_shell_docs.sh RASM_BINARY BUILD_DIR
set -uo pipefail
rasm=$1 build=$2
fail() { echo "FAIL: $*"; exit 1; }
commands=$("$rasm" help | awk '/^  [a-z]/{print $1}')
[[ -n $commands ]] || fail "rasm help lists no commands"

# --- the man page ---
[[ -s $build/rasm.1 ]] || fail "$build/rasm.1 was not generated"
if command -v groff >/dev/null; then
  warnings=$(groff -man -Tutf8 -ww -z "$build/rasm.1" 2>&1)
  [[ -z $warnings ]] || fail "groff warns about rasm.1: $warnings"
  text=$(groff -man -Tutf8 "$build/rasm.1" 2>/dev/null | sed 's/.\x08//g')
  for c in $commands; do
    grep -q "^       $c" <<<"$text" || fail "the man page does not document '$c'"
  done
  grep -q -- "--set section.key=value" <<<"$text" || fail "the man page lacks rasm run's usage"
  grep -q "^ *\-\-max\-frames N" <<<"$text" || grep -q -- "--max-frames N" <<<"$text" ||
    fail "the man page lacks rasm run's options"
else
  echo "note: groff not found, the man page was only checked for its commands"
  for c in $commands; do grep -q "^.B $c\$" "$build/rasm.1" || fail "rasm.1 lacks '$c'"; done
fi

# --- the bash completion ---
bash -n "$build/rasm.bash-completion" || fail "the completion is not valid bash"
# shellcheck disable=SC1091
source "$build/rasm.bash-completion"
complete_line() {  # complete_line WORD... : COMPREPLY for the last word
  COMP_WORDS=("$rasm" "$@")
  COMP_CWORD=$#
  COMPREPLY=()
  _rasm
  printf '%s\n' "${COMPREPLY[@]}"
}
expect() {  # expect WANTED WORD...
  local wanted=$1; shift
  complete_line "$@" | grep -qx -- "$wanted" || fail "completing '$*' does not offer '$wanted' (got: $(complete_line "$@" | tr '\n' ' '))"
}
expect run r
expect view vi
expect --out run --o
expect --set run --s
expect mapper.poses= run --set mapper.pos
expect exploration.planner= run --set exploration.pl
expect ate eval a
expect generate sim gen
expect --max-frames run --max-f
[[ -z $(complete_line run --set no_such_section.) ]] || fail "--set completes a key that does not exist"
# Every option a command's (or subcommand's) --help lists is offered after `rasm <command> [sub] --`.
for c in $commands; do
  subs=$("$rasm" "$c" --help | awk '/^subcommands/{s=1; next} /^$/{s=0} s && /^  [a-z]/{print $1}')
  invocations=$c  # a command made of subcommands: theirs
  [[ -z $subs ]] || invocations=$(for s in $subs; do echo "$c:$s"; done)
  for inv in $invocations; do
    read -ra words <<<"${inv/:/ }"
    opts=$("$rasm" "${words[@]}" --help | awk '/^options:/{o=1; next} /^$/{o=0}
      o && /^  -/{for (i = 1; i <= NF; i++) if ($i ~ /^--[a-z]/) {sub(/,$/, "", $i); print $i; break}}')
    [[ -n $opts ]] || fail "rasm ${words[*]} --help lists no options"
    offered=$(complete_line "${words[@]}" --)
    for o in $opts; do
      grep -qx -- "$o" <<<"$offered" || fail "completing 'rasm ${words[*]} --' does not offer $o"
    done
  done
done
echo "man page: $(wc -l <"$build/rasm.1") lines; completion: $(echo $commands | wc -w) commands, --set keys: $(_rasm_set_keys "$rasm" | wc -l)"
