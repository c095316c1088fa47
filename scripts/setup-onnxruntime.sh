#!/usr/bin/env bash
# Installs ONNX Runtime for `--perception maskrcnn` into the project: the shared library from the
# pinned `onnxruntime` wheel on PyPI (checked against its SHA-256), unpacked into
# .contphy/onnxruntime/. contphy-eval finds it there (or wherever ORT_DYLIB_PATH points).
# Needs python3 with pip (to fetch the wheel) and nothing else; safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

version="1.31.1"
wheel="onnxruntime-${version}-cp311-cp311-manylinux_2_28_x86_64.whl"
sha256="5752bd508126ae7c49894d3b9d2e83f0c3d487319246d04c444b393308d7ad7f"
target=".contphy/onnxruntime"
library="libonnxruntime.so.${version}"

if [ -f "${target}/${library}" ]; then
  echo "ONNX Runtime ${version} is installed: ${target}/${library}"
  exit 0
fi
if [ "$(uname -s)-$(uname -m)" != "Linux-x86_64" ]; then
  echo "setup-onnxruntime: only Linux x86_64 is supported here; set ORT_DYLIB_PATH to a libonnxruntime.so ${version} instead" >&2
  exit 1
fi

download=".contphy/downloads"
mkdir -p "${download}" "${target}"
if [ ! -f "${download}/${wheel}" ]; then
  echo "downloading ${wheel} (24 MB) ..."
  python3 -m pip download --quiet --no-deps --only-binary=:all: \
    --python-version 3.11 --platform manylinux_2_28_x86_64 \
    "onnxruntime==${version}" -d "${download}"
fi
echo "${sha256}  ${download}/${wheel}" | sha256sum --check --quiet

# Unpack only the library (a wheel is a zip file), then move it into place atomically.
python3 - "${download}/${wheel}" "${target}" "${library}" <<'PY'
import os, sys, zipfile
wheel, target, library = sys.argv[1:]
with zipfile.ZipFile(wheel) as archive:
    data = archive.read(f"onnxruntime/capi/{library}")
partial = os.path.join(target, library + ".partial")
with open(partial, "wb") as out:
    out.write(data)
os.replace(partial, os.path.join(target, library))
PY
echo "ONNX Runtime ${version} installed: ${target}/${library}"
