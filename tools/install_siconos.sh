#!/usr/bin/env bash
# Optional: Siconos (nonsmooth dynamics library) as a benchmark peer for the work-precision study
# (tools/siconos_peer.py, src/vibroimpact/peer_siconos.py; tests/test_peer_siconos.py skips without it).
# Debian's python3-siconos imports only under the system interpreter /usr/bin/python3, not the
# project's venv.  Needs root (Debian package); idempotent.  Usage: sudo tools/install_siconos.sh
# Prints the Debian package version (4.4.0+dfsg-2 on bookworm) and the module's own version string
# (the Debian build reports '4.5.0' there, from the development tree it was cut from).
set -euo pipefail
if ! /usr/bin/python3 -c "import siconos.kernel" >/dev/null 2>&1; then
    apt-get update -q
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q python3-siconos
fi
dpkg-query -W -f='python3-siconos ${Version}\n' python3-siconos
/usr/bin/python3 -c "import siconos; print('siconos module version', siconos.version)"
