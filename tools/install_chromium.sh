#!/usr/bin/env bash
# Optional: headless Chromium for the report render test (tests/test_report.py skips without it).
# Needs root (Debian package). Usage: sudo tools/install_chromium.sh
set -euo pipefail
apt-get update -q
DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium
chromium --version
