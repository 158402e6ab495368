#!/usr/bin/env bash
# The VTK-free core and its GoogleTest suite under AddressSanitizer + UndefinedBehaviorSanitizer
# (with float-cast-overflow, which -fsanitize=undefined leaves out in GCC: a NaN cast to an
# integer is undefined).
#   bash Utilities/run-sanitizers.sh
# (The ParaView plugin is not built in this mode: pvpython would need the ASan runtime
# preloaded into a non-instrumented interpreter.)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BRT_ASAN_BUILD_DIR:-$root/build-asan}
bash "$root/Utilities/install-deps.sh"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRT_SANITIZE=ON
cmake --build "$build" -j "$(nproc)"
cd "$build"
# OpenCASCADE keeps process-lifetime singletons (messenger, type registry) that LeakSanitizer
# reports as leaks at exit; they are not ours, so leak detection is off. Any other error aborts.
ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --output-on-failure -j "$(nproc)" -L core
