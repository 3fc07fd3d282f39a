#!/usr/bin/env bash
# FOV_REQUIRE_OPENCL=1 must turn the OpenCL tests' skip into a failure: run them ($1, a
# gtest binary) with no OpenCL platform visible (OCL_ICD_VENDORS: an empty folder).
set -uo pipefail
tests=$1
empty=$(mktemp -d)
trap 'rm -rf "$empty"' EXIT
failures=0
out=$(OCL_ICD_VENDORS=$empty FOV_REQUIRE_OPENCL=1 "$tests" --gtest_filter='device_fixture.KernelsReproduceAConstantField' 2>&1)
code=$?
if [[ $code -eq 0 ]] || ! grep -q "FOV_REQUIRE_OPENCL=1" <<<"$out"; then
  echo "FAIL with FOV_REQUIRE_OPENCL=1 and no platform: exit $code"; echo "$out" | tail -5; failures=$((failures + 1))
fi
out=$(env -u FOV_REQUIRE_OPENCL OCL_ICD_VENDORS=$empty "$tests" --gtest_filter='device_fixture.KernelsReproduceAConstantField' 2>&1)
code=$?
if [[ $code -ne 0 ]] || ! grep -q "SKIPPED" <<<"$out"; then
  echo "FAIL without FOV_REQUIRE_OPENCL and no platform: exit $code, expected a skip"; failures=$((failures + 1))
fi
echo "opencl_required: $((2 - failures)) passed, $failures failed"
[[ $failures -eq 0 ]]
