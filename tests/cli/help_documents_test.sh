#!/usr/bin/env bash
# help_documents_test.sh GRADMESH MAN_PAGE COMPLETION WORK_DIR: the man page and the bash
# completion made from the help text (app/help_documents.cpp) say what --help says, and the
# completion completes, run by bash itself.
set -euo pipefail
gradmesh=$1 man_page=$2 completion=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
fail() { echo "help documents test: $*" >&2; exit 1; }

# The man page: well-formed troff (no warnings), every command and option of the help in it.
rendered=$(LC_ALL=C.UTF-8 groff -man -Tutf8 -ww -z "$man_page" 2>&1) || fail "groff failed: $rendered"
[[ -z $rendered ]] || fail "groff warns: $rendered"
text=$(LC_ALL=C.UTF-8 groff -man -Tutf8 "$man_page" 2>/dev/null | sed 's/\x1b\[[0-9;]*m//g; s/.\x08//g')
for command in convert render info view compare batch sample; do
  grep -q "^   $command\$" <<<"$text" || grep -q "^ *$command\$" <<<"$text" || fail "no section for $command"
  while read -r option; do
    grep -qF -- "$option" <<<"$text" || fail "$command's $option missing from the man page"
  done < <("$gradmesh" "$command" --help | grep -oE '^  (-[a-z], )?--[a-z-]+' | grep -oE -- '--[a-z-]+')
done
grep -qF -- "--quiet" <<<"$text" || fail "--quiet missing from the man page"

# The completion, as bash calls it.
# shellcheck disable=SC1090
source "$completion"
complete_words() {  # complete_words WORD... : COMPREPLY for the last word, one per line
  COMP_WORDS=("$@")
  COMP_CWORD=$((${#COMP_WORDS[@]} - 1))
  COMPREPLY=()
  _gradmesh
  printf '%s\n' "${COMPREPLY[@]}" | sort
}
cd "$work"
touch in.png photo.JPG mesh.gmb drawing.svg notes.txt
mkdir folder
[[ $(complete_words gradmesh con) == convert ]] || fail "command: $(complete_words gradmesh con)"
[[ $(complete_words gradmesh convert --ou) == $'--output\n--output-dir' ]] || fail "convert --ou: $(complete_words gradmesh convert --ou)"
complete_words gradmesh convert --q | grep -qx -- --quiet || fail "convert --quiet not offered"
complete_words gradmesh batch --max-e | grep -qx -- --max-error || fail "batch lacks convert's options"
complete_words gradmesh batch --ma | grep -qx -- --mask && fail "batch offers --mask"
# Inputs by extension (either case), and folders; not the text file.
[[ $(complete_words gradmesh convert '') == $'drawing.svg\nfolder\nin.png\nmesh.gmb\nphoto.JPG' ]] ||
  fail "convert inputs: $(complete_words gradmesh convert '')"
[[ $(complete_words gradmesh render '') == $'drawing.svg\nfolder\nmesh.gmb' ]] || fail "render inputs: $(complete_words gradmesh render '')"
[[ $(complete_words gradmesh render in.gmb -o '') == $'folder\nin.png\nphoto.JPG' ]] || fail "render outputs: $(complete_words gradmesh render in.gmb -o '')"
[[ $(complete_words gradmesh convert in.png --to s) == $'svg\nsvgz' ]] || fail "--to: $(complete_words gradmesh convert in.png --to s)"
[[ $(complete_words gradmesh convert in.png --output-dir '') == folder ]] || fail "--output-dir: $(complete_words gradmesh convert in.png --output-dir '')"
[[ -z $(complete_words gradmesh convert in.png --max-error '') ]] || fail "a value got completions"
echo "help documents test: passed"
