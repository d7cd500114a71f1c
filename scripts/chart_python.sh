#!/usr/bin/env bash
# Prints the Python that draws igi's charts: Debian's /usr/bin/python3 with python3-matplotlib and
# python3-numpy, installed with apt when missing (as root). Exits 1 with a message when it cannot
# provide them, so callers can go on without charts.
set -euo pipefail
python=/usr/bin/python3
if ! "$python" -c 'import matplotlib, numpy' 2>/dev/null; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "igi: installing python3-matplotlib python3-numpy" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-matplotlib python3-numpy >/dev/null 2>&1 || true
  fi
  if ! "$python" -c 'import matplotlib, numpy' 2>/dev/null; then
    echo "igi: no $python with matplotlib and numpy (apt-get install python3-matplotlib python3-numpy)" >&2
    exit 1
  fi
fi
echo "$python"
