#!/bin/bash
# The size of the code a GPU compiler makes of the kernel source, measured without a GPU: clang
# compiles Kernels/thickness.cl to NVIDIA's PTX (libclc's built-ins linked in) with every call
# inlined that the source lets it inline, as NVIDIA's OpenCL compiler does. The test fails when
# one function or the whole program is larger than the limits: a kernel that grows past them
# takes the driver's PTX assembler minutes (docs/Solver.md, "Compile time on GPUs").
#
#   Testing/KernelGpuCodeSize.sh SOURCE WORKDIR [CLANG-FLAGS...]
#
# Limits in PTX lines; BRT_PTX_MAX_FUNCTION and BRT_PTX_MAX_TOTAL override them. Exit 77 (skipped)
# when clang-14, llvm-14 or libclc-14 is missing (Utilities/install-deps.sh installs them).
set -u
src=${1:?source}
work=${2:?workdir}
shift 2
maxFunction=${BRT_PTX_MAX_FUNCTION:-12000}
maxTotal=${BRT_PTX_MAX_TOTAL:-150000}
clc=/usr/lib/clc/nvptx64--nvidiacl.bc
for tool in clang-14 llvm-link-14 opt-14 llc-14; do
  command -v $tool > /dev/null || { echo "KernelGpuCodeSize: $tool not found, skipped"; exit 77; }
done
[ -f $clc ] || { echo "KernelGpuCodeSize: $clc not found (libclc-14), skipped"; exit 77; }
mkdir -p "$work" || exit 1
rc=0
for precision in float double; do
  flags=()
  [ $precision = double ] && flags=(-DBRT_DOUBLE)
  out=$work/thickness-$precision
  clang-14 -x cl -cl-std=CL1.2 -target nvptx64-nvidia-nvcl -Xclang -finclude-default-header \
    -D__OPENCL_VERSION__=120 "${flags[@]}" "$@" -O3 -emit-llvm -c "$src" -o $out.bc &&
    llvm-link-14 $out.bc $clc -o $out.linked.bc 2> /dev/null &&
    opt-14 -O3 -inline-threshold=100000 $out.linked.bc -o $out.opt.bc &&
    llc-14 -mcpu=sm_70 -O3 $out.opt.bc -o $out.ptx || { echo "KernelGpuCodeSize: $precision did not compile"; exit 1; }
  # Lines per function (.func and .entry), largest first.
  awk '/^\.(visible )?(func|entry)/ { if (name != "") print n, name; n = 0;
         name = $0; sub(/\($/, "", name); sub(/.*[ )]/, "", name) }
       { n++ } END { print n, name }' $out.ptx | sort -rn > $out.sizes
  total=$(wc -l < $out.ptx)
  read -r largest largestName < $out.sizes
  echo "$precision: $total PTX lines, largest function $largestName with $largest (limits $maxTotal, $maxFunction)"
  head -5 $out.sizes | sed 's/^/  /'
  if [ "$largest" -gt "$maxFunction" ] || [ "$total" -gt "$maxTotal" ]; then
    echo "KernelGpuCodeSize: $precision over the limit: mark the large functions it inlines BRT_SPLIT"
    rc=1
  fi
done
exit $rc
