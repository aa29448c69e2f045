#!/usr/bin/env bash
# expect_fail.sh REGEX CMD [ARGS...]: passes when CMD exits non-zero and the last line it
# printed on stderr matches REGEX (used by the CLI error-path tests).
re=$1; shift
err=$("$@" 2>&1 >/dev/null)
rc=$?
if [ $rc -eq 0 ]; then echo "expected a failure, got exit 0"; exit 1; fi
if ! printf '%s\n' "$err" | tail -n 1 | grep -Eq -- "$re"; then
  echo "exit $rc, but stderr did not match '$re':"; printf '%s\n' "$err"; exit 1
fi
echo "ok (exit $rc): $(printf '%s\n' "$err" | tail -n 1)"
