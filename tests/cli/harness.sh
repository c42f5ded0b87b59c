#!/usr/bin/env bash
# Sourced by the CLI test scripts that take PATH_TO_INFOCUS SHARED_DATA_DIR: sets $bin and $data
# from the arguments, a scratch directory $tmp removed on exit, and the pass/fail counters that
# ok and bad keep (the script ends by reporting them).
set -u
bin=${1:?path to infocus}
data=${2:?shared data dir}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }
