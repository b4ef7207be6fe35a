#!/usr/bin/env bash
# Creates tools/oracle/.venv with pydrake and numpy (the oracle that writes tests/fixtures).
# Needed only to regenerate fixtures or run the Drake side of benchmarks; `cargo test` does not need it.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if [ ! -x "$here/.venv/bin/python" ]; then
  python3 -m venv "$here/.venv"
fi
"$here/.venv/bin/pip" install --quiet -r "$here/requirements.txt"
"$here/.venv/bin/python" -c "import pydrake, numpy, pinocchio; print('oracle ready: drake', pydrake.__file__)"
