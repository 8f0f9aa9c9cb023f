#!/usr/bin/env bash
# Rebuild constraints.txt: install requirements.txt, requirements-test.txt and requirements-docs.txt into a fresh virtual
# environment and record every installed distribution's exact version. Run after changing a pin.
set -euo pipefail
cd "$(dirname "$0")/.."
env=$(mktemp -d)/venv
"${PYTHON:-python3}" -m venv "$env"
"$env/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade pip
"$env/bin/python" -m pip install --quiet --disable-pip-version-check -r requirements.txt -r requirements-test.txt -r requirements-docs.txt
{
    echo "# Every distribution of heatdata's environment, exact (scripts/lock.sh; $("$env/bin/python" --version))."
    echo "# scripts/setup.sh installs with -c constraints.txt, so a fresh machine gets this same stack."
    "$env/bin/python" -m pip freeze --all
} > constraints.txt
rm -rf "$(dirname "$env")"
echo "lock: constraints.txt holds $(grep -c '==' constraints.txt) pins"
