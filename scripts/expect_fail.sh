#!/usr/bin/env bash
# expect_fail.sh [--rc N] REGEX CMD [ARGS...]: passes when CMD exits non-zero (exactly N with
# --rc: 2 is a bad command line, 1 a failed input or computation) and the last line it printed
# on stderr matches REGEX (used by the CLI error-path tests).
want=""
if [ "$1" = "--rc" ]; then want=$2; shift 2; fi
re=$1; shift
err=$("$@" 2>&1 >/dev/null)
rc=$?
if [ $rc -eq 0 ]; then echo "expected a failure, got exit 0"; exit 1; fi
if [ -n "$want" ] && [ "$rc" -ne "$want" ]; then
  echo "expected exit $want, got $rc:"; printf '%s\n' "$err"; exit 1
fi
if ! printf '%s\n' "$err" | tail -n 1 | grep -Eq -- "$re"; then
  echo "exit $rc, but stderr did not match '$re':"; printf '%s\n' "$err"; exit 1
fi
echo "ok (exit $rc): $(printf '%s\n' "$err" | tail -n 1)"
