# Shared by the CLI test scripts: check NAME EXPECTED_CODE -- COMMAND...
# passes when the exit code matches and, for failures, stderr is one line "TOOL: ...".
failures=0
passes=0
check() {
  local name=$1 want=$2; shift 3
  local err code lines
  err=$("$@" 2>&1 >/dev/null); code=$?
  lines=$(printf '%s' "$err" | grep -c '' || true)
  if [[ $code -ne $want ]]; then
    echo "FAIL $name: exit $code, wanted $want: $err"; failures=$((failures + 1))
  elif [[ $want -ne 0 && ( $lines -ne 1 || "$err" != "$tool:"* ) ]]; then
    echo "FAIL $name: wanted one '$tool: ...' line, got: $err"; failures=$((failures + 1))
  else
    passes=$((passes + 1))
  fi
}
# fail DESCRIPTION: records a failed property check.
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
