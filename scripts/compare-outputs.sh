#!/usr/bin/env bash
# Compares two output folders file by file, leaving out what records how a file was made
# (the provenance: tool version, git hash, command line), so that two builds of a refactor
# can be shown to make the same outputs (docs/architecture.md, "Refactoring"):
#   PNG, TIFF   the pixels (oiiotool --diff, no tolerance)
#   .dv         every byte after the header (blocks, index, basins; the header holds the
#               provenance), or, when the provenances differ in length, every layer decoded
#               (terrain-inspect export --to tif of $TERRAIN_BIN or build/bin)
#   .ply        every byte after end_header
#   .svg        the text without its <desc> (the provenance)
#   .pdf        the pages rasterized at 96 dpi (cairo writes the creation date)
#   other       the text with each folder's own path as DIR, provenance lines and lines
#               starting with '#' left out; timings (timings.csv, summary.txt) are not compared
# Usage: scripts/compare-outputs.sh BEFORE_DIR AFTER_DIR; prints one line per difference and
# exits 1 if there is any.
set -uo pipefail
a="$1" b="$2"
inspect="${TERRAIN_BIN:-$(dirname "$0")/../build/bin}/terrain-inspect"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
differ=0 same=0
while IFS= read -r -d '' f; do
  rel="${f#$a/}" g="$b/${f#$a/}"
  if [ ! -e "$g" ]; then echo "missing: $rel"; differ=$((differ + 1)); continue; fi
  case "$f" in
    *.png|*.tif) oiiotool --fail 0 --failpercent 0 --diff "$f" "$g" >/dev/null 2>&1; ok=$? ;;
    *.dv) skip=$(od -An -tu4 -j12 -N4 "$f" | tr -d ' '); skip2=$(od -An -tu4 -j12 -N4 "$g" | tr -d ' ')
          if [ "$skip" = "$skip2" ]; then
            cmp -s <(tail -c +$((skip + 1)) "$f") <(tail -c +$((skip + 1)) "$g"); ok=$?
          else  # provenances of other lengths move the blocks: every layer, decoded
            "$inspect" export "$f" --to tif -o "$tmp/da" -q >/dev/null && "$inspect" export "$g" --to tif -o "$tmp/db" -q >/dev/null
            ok=$?
            for t in "$tmp"/da/*.tif; do [ $ok -eq 0 ] || break; oiiotool --fail 0 --failpercent 0 --diff "$t" "$tmp/db/${t##*/}" >/dev/null 2>&1 || ok=1; done
            rm -rf "$tmp/da" "$tmp/db"
          fi ;;
    *.ply) cmp -s <(sed -n '/^end_header$/,$p' "$f") <(sed -n '/^end_header$/,$p' "$g"); ok=$? ;;
    *.svg) cmp -s <(sed 's|<desc>[^<]*</desc>||' "$f") <(sed 's|<desc>[^<]*</desc>||' "$g"); ok=$? ;;
    *.pdf) pdftoppm -png -r 96 "$f" "$tmp/a" && pdftoppm -png -r 96 "$g" "$tmp/b" && \
           for p in "$tmp"/a*.png; do oiiotool --fail 0 --failpercent 0 --diff "$p" "$tmp/b${p#$tmp/a}" >/dev/null 2>&1 || exit 1; done
           ok=$?; rm -f "$tmp"/a*.png "$tmp"/b*.png ;;
    *.gpkg|*.aux.xml|*timings.csv|*summary.txt) ok=0 ;;  # times and provenance; their data come from files compared here
    *) cmp -s <(sed "s|$a|DIR|g" "$f" | grep -v '^#\|provenance\|(git ') <(sed "s|$b|DIR|g" "$g" | grep -v '^#\|provenance\|(git ')
       ok=$? ;;
  esac
  if [ "$ok" -eq 0 ]; then same=$((same + 1)); else echo "differs: $rel"; differ=$((differ + 1)); fi
done < <(find "$a" -type f -print0 | sort -z)
echo "same: $same, different: $differ"
[ "$differ" -eq 0 ]
