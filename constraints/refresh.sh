#!/usr/bin/env bash
# Rebuilds constraints/ci.txt from the newest releases: a fresh venv, the newest versions
# of every dependency, the whole test suite, and only if it passes the new pins.
# Usage (from anywhere): constraints/refresh.sh
set -euo pipefail
cd "$(dirname "$0")/.."
venv=$(mktemp -d)/venv
python3 -m venv "$venv"
"$venv/bin/pip" install -U pip
"$venv/bin/pip" install -U -e ".[test]"
"$venv/bin/python" -m pytest
"$venv/bin/pip" freeze --exclude-editable | grep -v -i '^idkit' > constraints/ci.txt
echo "constraints/ci.txt refreshed from $venv; review with: git diff constraints/ci.txt"
