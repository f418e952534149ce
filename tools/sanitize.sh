#!/usr/bin/env bash
# Build deployfx's core and module with AddressSanitizer and UndefinedBehaviorSanitizer into their
# own build directory and run the pytest suite against that build (docs/reliability.md).
#
#   tools/sanitize.sh [pytest arguments...]     e.g. tools/sanitize.sh -m "not slow" -x
#
# Environment: PYTHON (default: python3 on PATH; it needs numpy, scipy, pybind11, cmeel-eigen,
# ninja and the test extra), BUILD_DIR (default: build/sanitize), SANITIZE (default:
# address,undefined), JOBS (default: 2), CXX (the compiler, GCC or Clang, on the first configure). The instrumented module is put first on PYTHONPATH through
# a copy of python/deployfx in BUILD_DIR, so the source tree's own _core is left alone.
# Python itself is not instrumented: the ASan runtime is LD_PRELOADed, leak detection is off (the
# interpreter keeps its objects at exit). Every report is written to BUILD_DIR/reports/; the script
# fails if pytest fails or if any report was written.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
PYTHON=${PYTHON:-python3}
BUILD_DIR=${BUILD_DIR:-$root/build/sanitize}
SANITIZE=${SANITIZE:-address,undefined}
JOBS=${JOBS:-2}
CXX_FOR_RUNTIME=${CXX:-g++}  # the compiler whose sanitizer runtimes are preloaded

start=$(date +%s)
mkdir -p "$BUILD_DIR"
pybind11_dir=$("$PYTHON" -c "import pybind11; print(pybind11.get_cmake_dir())")
# -O1 -g without NDEBUG: Eigen's and the core's assertions stay on, stack traces stay readable.
cmake -S "$root" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DDEPLOYFX_SANITIZE="$SANITIZE" -DPython_EXECUTABLE="$(command -v "$PYTHON")" \
  -Dpybind11_DIR="$pybind11_dir" >/dev/null
nice cmake --build "$BUILD_DIR" -j "$JOBS"
built=$(date +%s)

# A package tree whose _core is the instrumented one.
pkg="$BUILD_DIR/python"
rm -rf "$pkg"
mkdir -p "$pkg"
cp -r "$root/python/deployfx" "$pkg/"
find "$pkg" -name '_core*.so' -delete
cp "$BUILD_DIR"/_core*.so "$pkg/deployfx/"

reports="$BUILD_DIR/reports"
rm -rf "$reports"
mkdir -p "$reports"
preload=""
case ",$SANITIZE," in
  *,address,*) preload=$("$CXX_FOR_RUNTIME" -print-file-name=libasan.so) ;;
esac
case ",$SANITIZE," in
  *,undefined,*) preload="$preload${preload:+ }$("$CXX_FOR_RUNTIME" -print-file-name=libubsan.so)" ;;
esac

status=0
(
  cd "$root"
  export PYTHONPATH="$pkg${PYTHONPATH:+:$PYTHONPATH}"
  export LD_PRELOAD="$preload"
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:log_path=$reports/asan"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=0:log_path=$reports/ubsan"
  # Import check: the instrumented module must be the one tested.
  "$PYTHON" -c "import deployfx, sys; assert deployfx.__file__.startswith('$pkg'), deployfx.__file__"
  nice "$PYTHON" -m pytest -p no:cacheprovider "$@"
) || status=$?
end=$(date +%s)

echo "sanitize.sh: build $((built - start)) s, tests $((end - built)) s, pytest exit status $status"
if compgen -G "$reports/*" >/dev/null; then
  echo "sanitize.sh: sanitizer reports in $reports:" >&2
  for f in "$reports"/*; do
    echo "---- $f" >&2
    head -n 40 "$f" >&2
  done
  exit 1
fi
echo "sanitize.sh: no sanitizer reports ($SANITIZE)"
exit "$status"
