#!/usr/bin/env bash
# The Python package's CI step: a fresh venv under target/, the package installed with pip
# as a user would (`pip install ./crates/trundle-py`, maturin as the build backend, a
# release build), the `trundle` command to compare with, and the pytest tests. Run from
# anywhere; .ci/run calls it after `cargo test --workspace` with TRUNDLE_BIN set. Needs
# python3 with venv, and PyPI reachable.
set -euo pipefail
cd "$(dirname "$0")/../.."
started=$(date +%s)

python3 -c 'import venv, ensurepip' ||
  { echo "FAILED: python3 with venv is needed for the Python package's tests"; exit 1; }
rm -rf target/py-venv
python3 -m venv target/py-venv
py=target/py-venv/bin/python
"$py" -m pip install --disable-pip-version-check -q -r crates/trundle-py/tests/requirements.txt ||
  { echo "FAILED: pip could not install crates/trundle-py/tests/requirements.txt (is PyPI reachable?)"; exit 1; }
"$py" -m pip install --disable-pip-version-check -q ./crates/trundle-py
echo "Python package installed: $(( $(date +%s) - started )) s"

# The command to compare with: $TRUNDLE_BIN (.ci/run passes the one `cargo test --workspace`
# built, target/debug/trundle, so nothing is built twice), else a release build of it.
if [ -z "${TRUNDLE_BIN:-}" ]; then
  cargo build --release --locked -p trundle-cli
  TRUNDLE_BIN="$PWD/target/release/trundle"
fi
[ -x "$TRUNDLE_BIN" ] || { echo "FAILED: TRUNDLE_BIN=$TRUNDLE_BIN is not an executable trundle command"; exit 1; }
TRUNDLE_BIN="$TRUNDLE_BIN" "$py" -m pytest -q -p no:cacheprovider crates/trundle-py/tests
echo "Python package step: $(( $(date +%s) - started )) s"
