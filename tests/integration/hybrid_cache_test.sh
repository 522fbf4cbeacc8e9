# A hybrid object's visual map and force gain are computed on its first
# start and kept (services/deformable: HCOSIM_CACHE, else OUT/cache): the
# deformable services of deploy/default.yaml (the 3 cm cube and the
# organ) and deploy/press.yaml (the 10 cm cube), started in turn on an
# empty cache, each write a map and a gain per hybrid object; started
# again, they read them and rewrite none. A ctest fixture: the cache is
# then added to the one the other integration tests share (lib.sh), so
# that none of them pays for a first start while others load the machine.
source "$(dirname "$0")/lib.sh"
from_deploy default.yaml
from_deploy press.yaml
cache=$WORK/cache

# objects FILE RUN: FILE's deformable service `objects` alone for 0.2 s of
# real time on $cache, its log in $WORK/RUN.log
objects() {
  HCOSIM_CACHE=$cache limit 150 "$BIN/hcosim_deformable" --name objects --rate 1000 \
    --domain "$DOMAIN" --mode realtime --duration 0.2 --deployment "$WORK/$1" --out "$WORK/out-$2" \
    >"$WORK/$2.log" 2>&1 || fail "the objects of $1 exited $? ($2)"
}

objects default.yaml first
for o in cube organ; do grep -q "^$o: built in" "$WORK/first.log" || fail "$o was not built"; done
objects press.yaml first-press
grep -q "^cube: built in" "$WORK/first-press.log" || fail "the press scene's cube was not built"
maps=$(ls "$cache"/map-*.bin 2>/dev/null | wc -l)
gains=$(ls "$cache"/gain-*.bin 2>/dev/null | wc -l)
[ "$maps" -eq 3 ] && [ "$gains" -eq 3 ] || fail "a first start kept $maps maps and $gains gains, not 3 and 3"
before=$(cd "$cache" && stat -c '%n %Y %s' ./* | sort)
sum=$(cd "$cache" && md5sum ./* | sort)

# A second start: nothing is written again (a file would be renamed into
# place, a new one beside it).
sleep 1.1
objects default.yaml second
objects press.yaml second-press
[ "$(cd "$cache" && stat -c '%n %Y %s' ./* | sort)" = "$before" ] || fail "a second start rewrote the cache"
[ "$(cd "$cache" && md5sum ./* | sort)" = "$sum" ] || fail "the cache changed"

mkdir -p "$HCOSIM_CACHE"
cp -n "$cache"/* "$HCOSIM_CACHE"/
built=$(sed -nE 's/^(cube|organ): built in (.*)/\1 \2/p' "$WORK/first.log" | tr '\n' ' ')
echo "hybrid_cache_test: ok ($maps maps, $gains gains; the default scene's first start: ${built% })"
