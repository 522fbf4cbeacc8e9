# DDS Security: hcosim security init's credentials, a secure deployment
# whose DeformedMesh reaches an authorized reader and nobody else, a
# subscribe-only identity that cannot publish, clear errors.
source "$(dirname "$0")/lib.sh"
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$WORK"

# deploy/secure.yaml is deploy/default.yaml plus its security section.
diff <(sed -n '/^domain:/,$p' "$ROOT/deploy/default.yaml") <(sed -n '/^domain:/,$p' "$ROOT/deploy/secure.yaml") ||
  fail "deploy/secure.yaml's scene and services differ from deploy/default.yaml's"
grep -q '^security: {dir: ../out/security}$' "$ROOT/deploy/secure.yaml" || fail "deploy/secure.yaml has no security section"

cube_alone plain.yaml 14
{ echo "security: {dir: keys}"; cat plain.yaml; } >secure.yaml

# Credentials: the tools, the clock, each service, and a reader.
"$BIN/hcosim" security init --deployment secure.yaml --readers viewer >init.log 2>&1 || fail "security init exited $?"
for id in hcosim clock objects viewer; do
  openssl verify -CAfile keys/ca.pem "keys/identities/$id.pem" >/dev/null || fail "$id's certificate is not signed by the CA"
  [ "$(stat -c %a "keys/identities/$id.key")" = 600 ] || fail "$id's private key is readable by others"
done
openssl smime -verify -in keys/permissions.p7s -CAfile keys/ca.pem -text >perm.xml 2>/dev/null ||
  fail "permissions.p7s is not signed by the CA"
grep -q "<subject_name>CN=viewer</subject_name>" perm.xml || fail "no grant for viewer: $(cat perm.xml)"
[ "$(grep -c '<publish>' perm.xml)" -eq 3 ] || fail "expected publish grants for hcosim, clock, objects only"
openssl smime -verify -in keys/governance.p7s -CAfile keys/ca.pem -text 2>/dev/null |
  grep -q "<data_protection_kind>ENCRYPT</data_protection_kind>" || fail "governance does not encrypt data"
# A second CA: certificates the deployment does not trust.
"$BIN/hcosim" security init other --identities hcosim >other.log 2>&1 || fail "second security init exited $?"

# Refusals, each naming the problem.
err=$("$BIN/hcosim" security init --deployment secure.yaml 2>&1); code=$?
[ $code -eq 2 ] && echo "$err" | grep -q "already holds a CA" || fail "re-init: exit $code: $err"
"$BIN/hcosim" security init --deployment secure.yaml --keep | grep -q "keeping the credentials" || fail "--keep"
err=$("$BIN/hcosim" security init --deployment plain.yaml 2>&1); code=$?
[ $code -eq 2 ] && echo "$err" | grep -q "needs a DIR" || fail "init without a folder: exit $code: $err"
err=$("$BIN/hcosim" security init x --protection most 2>&1); code=$?
[ $code -eq 2 ] && echo "$err" | grep -q -- "--protection: most not in {data,all}" || fail "bad --protection: exit $code: $err"
{ echo "security: {dir: nokeys}"; cat plain.yaml; } >missing.yaml
err=$("$BIN/hcosim" up missing.yaml --out out_missing 2>&1); code=$?
[ $code -eq 2 ] && echo "$err" | grep -q "missing.yaml:1:11: DDS Security: cannot read .*nokeys/ca.pem" ||
  fail "missing credentials: exit $code: $err"
echo "$err" | grep -q "hcosim security init" || fail "the error does not say how to make credentials: $err"

# The secure run, and four participants beside it.
start up "$BIN/hcosim" up secure.yaml --out out
# The readers' timeouts count from when the cube's loop runs: building its
# visual map takes seconds (about 10 under AddressSanitizer).
for i in $(seq 900); do grep -q "every service running" up.log && break; sleep 0.1; done
grep -q "every service running" up.log || fail "the secure deployment did not start in 90 s: $(cat up.log)"
start authorized "$BIN/hcosim" echo DeformedMesh --count 2 --timeout 10 --security keys --identity viewer
start anonymous "$BIN/hcosim" echo DeformedMesh --count 1 --timeout 8
start foreign "$BIN/hcosim" echo DeformedMesh --count 1 --timeout 8 --security other
# viewer may only subscribe: as a service it is refused its first writer.
cat >probe.yaml <<YAML
domain: $DOMAIN
security: {dir: keys}
services:
  - {name: viewer, kind: test_probe, rate: 100, params: {role: source}}
YAML
start publisher "$HCOSIM_SERVICE_PATH/hcosim_test_probe" --name viewer --rate 100 --domain "$DOMAIN" --deployment probe.yaml
for p in "${PIDS[@]:1}"; do wait "$p"; done
wait "${PIDS[0]}" || fail "the secure deployment exited $?"

n=$(grep -c '^{"mesh":"cube"' authorized.log)
[ "$n" -eq 2 ] || fail "the authorized reader got $n of 2 DeformedMesh samples"
grep -q "0 of 1 samples of DeformedMesh" anonymous.log || fail "a participant without credentials got: $(head -c 300 anonymous.log)"
grep -q "0 of 1 samples of DeformedMesh" foreign.log || fail "a participant of another CA got: $(head -c 300 foreign.log)"
grep -q "cannot create a writer for" publisher.log || fail "viewer published: $(tail -n 5 publisher.log)"
grep -q "DDS Security on" up.log || fail "up does not say security is on"
grep -q "every service joined" up.log || fail "up did not see its services join: $(cat up.log)"
echo "security_test: ok"
