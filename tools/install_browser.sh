#!/usr/bin/env bash
# Install the headless browser driven by tests/browser (Debian's `chromium` package).
#
# Idempotent and never fatal: when Chromium is already there it only says so; when
# it cannot be installed (not root, no apt-get, no network) it prints why, and the
# browser test is then SKIPPED with that reason (never silently passed).
# Usage: bash tools/install_browser.sh     (POINSOT_CHROMIUM overrides the path)
set -u
CHROMIUM="${POINSOT_CHROMIUM:-/usr/bin/chromium}"
say() { echo "install_browser: $*" >&2; }

if [ -x "$CHROMIUM" ]; then
    say "found $CHROMIUM ($("$CHROMIUM" --version 2>/dev/null | head -n 1))"
    exit 0
fi
if [ "$(id -u)" != "0" ]; then
    say "WARNING: $CHROMIUM is missing and this is not root, so 'apt-get install chromium'"
    say "cannot run; install it yourself (sudo apt-get install chromium) or the browser test is skipped."
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    say "WARNING: $CHROMIUM is missing and apt-get is not available (not Debian/Ubuntu);"
    say "install Chromium and set POINSOT_CHROMIUM, or the browser test is skipped."
    exit 0
fi
export DEBIAN_FRONTEND=noninteractive
say "installing Debian's chromium (apt-get update && apt-get install -y chromium) ..."
if ! apt-get update -qq; then
    say "WARNING: apt-get update failed; trying the install with the current package lists."
fi
if apt-get install -y -qq chromium >/dev/null; then
    say "installed: $("$CHROMIUM" --version 2>/dev/null | head -n 1)"
else
    say "WARNING: 'apt-get install -y chromium' failed; the browser test will be skipped."
fi
exit 0
