#!/bin/sh
# The out-of-tree example (examples/external-strategy) against an installed BeamContact: install the
# build tree to a scratch prefix, build the plug-in with find_package(BeamContact), check its tangent
# against central differences, run its study with the installed program from a folder holding only
# the two decks, check the study's normal forces against their closed form, and render a case.
# The installed libraries' SONAME versions, docs and decks, and the docs folder --help names are
# checked first.
# Usage: external_strategy.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
build=$1 src=$2 work=$3
rm -rf "$work"
mkdir -p "$work/decks"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
# Each installed library carries its version: the file libbeamcontact_X.so.0.1.0 and the SONAME
# libbeamcontact_X.so.0.1 (major.minor while the major version is 0; CHANGELOG.md, "Versions").
version=$("$work/prefix/bin/beamcontact" --version | sed -n 's/^beamcontact //p')
case $version in 0.*) soversion=${version%.*} ;; *) soversion=${version%%.*} ;; esac
for lib in core linalg elements constraints input; do
  file=$(find "$work/prefix" -name "libbeamcontact_$lib.so.$version")
  test -n "$file" || { echo "libbeamcontact_$lib.so.$version is not installed"; exit 1; }
  readelf -d "$file" | grep -q "(SONAME) .*\[libbeamcontact_$lib.so.$soversion\]" ||
    { echo "libbeamcontact_$lib: SONAME is not libbeamcontact_$lib.so.$soversion"; exit 1; }
done
# The documentation (with the figures it shows), the example decks and the study decks are installed
# in share/beamcontact, and the installed program's --help names that docs folder (the build tree's
# names the sources').
share="$work/prefix/share/beamcontact"
for f in "$src"/docs/*.md; do
  test -f "$share/docs/${f##*/}" || { echo "docs/${f##*/} is not installed"; exit 1; }
done
for figure in $(grep -oh 'figures/[A-Za-z0-9_.-]*\.png' "$src"/docs/*.md | sort -u); do
  test -f "$src/docs/$figure" || { echo "docs cite $figure, which docs/ lacks"; exit 1; }
  test -f "$share/docs/$figure" || { echo "docs/$figure is not installed"; exit 1; }
done
for deck in "$src"/input/*.xml "$src"/input/studies/*.xml; do
  test -f "$share/input/${deck#"$src/input/"}" || { echo "${deck#"$src/"} is not installed"; exit 1; }
done
docs=$("$work/prefix/bin/beamcontact" --help | sed -n 's/^docs\/ above is \(.*\) (the documentation)$/\1/p')
test "$docs" = "$(cd "$share/docs" && pwd -P)" || { echo "installed --help names docs \"$docs\""; exit 1; }
test -f "$docs/input.md"
"$work/prefix/bin/beamcontact" study --help | grep -q "^docs/ above is $docs "
docs=$("$build/drivers/beamcontact" --help | sed -n 's/^docs\/ above is \(.*\) (the documentation)$/\1/p')
test "$docs" = "$(cd "$src/docs" && pwd -P)" || { echo "the build tree's --help names docs \"$docs\""; exit 1; }
# An installed study deck finds its base deck (input/studies/../example1.xml) and the example decks read.
"$work/prefix/bin/beamcontact" check "$share/input/example1.xml" > /dev/null
cmake -S "$src/examples/external-strategy" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" \
  > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/example" -j 2 > "$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
"$work/example/check_tangent"
cp "$src/examples/external-strategy/study.xml" "$src/examples/external-strategy/press.xml" "$work/decks/"
cd "$work/decks"
"$work/prefix/bin/beamcontact" study study.xml --plugin "$work/example/libquadratic_penalty.so" --output "$work/study"
/usr/bin/python3 "$src/examples/external-strategy/check_study.py" "$work/study"
"$work/prefix/bin/beamcontact" render "$work/study/cases/003" "$work/case3.png"
test -s "$work/case3.png"
# The deck's own Plugins (a path relative to the deck's folder) names what it needs: without --plugin
# it is refused before anything is loaded, with --plugin it runs.
cp "$work/example/libquadratic_penalty.so" "$work/decks/"
/usr/bin/python3 - "$work/decks/press.xml" "$work/decks/press_plugins.xml" <<'PY'
import sys
import xml.etree.ElementTree as ET
tree = ET.parse(sys.argv[1])
ET.SubElement(tree.getroot(), "Parameter", name="Plugins", type="Array(string)", value="{libquadratic_penalty.so}")
tree.write(sys.argv[2])
PY
if "$work/prefix/bin/beamcontact" run press_plugins.xml --output "$work/deck_plugins" --quiet 2> "$work/refused.txt"; then
  echo "a deck's Plugins was loaded without --plugin"; exit 1
fi
grep -q "the deck asks to load the plug-in .*libquadratic_penalty.so" "$work/refused.txt"
test ! -e "$work/deck_plugins"
"$work/prefix/bin/beamcontact" run press_plugins.xml --output "$work/deck_plugins" --quiet --plugin libquadratic_penalty.so
grep -q "^complete" "$work/deck_plugins/status.txt"
grep -q "^plug-in: .*libquadratic_penalty.so sha256 [0-9a-f]*$" "$work/deck_plugins/status.txt"
grep -q 'name="Type" type="string" value="Quadratic Penalty"' "$work/deck_plugins/effective_parameters.xml"
echo "external strategy: ok"
