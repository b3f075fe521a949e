#!/bin/bash
# CPU against CUDA backend on a GPU machine (benchmarks/sph_backends/compare_backends.cc).
# Build here (nvcc needed, no GPU): make -C build sph_backend_compare; copy the binary (and
# libgomp.so.1 if the GPU machine lacks it) into DIR and run this script there:
#   run_on_gpu.sh DIR
set -e
dir=${1:-.}
export LD_LIBRARY_PATH=$dir:$LD_LIBRARY_PATH
nvidia-smi -L || true
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(nproc)}
echo "CPU backend with OMP_NUM_THREADS=$OMP_NUM_THREADS"
"$dir/sph_backend_compare" 20 300 both   # a/20: 800 fluid particles
"$dir/sph_backend_compare" 40 300 both   # a/40: 3,200
"$dir/sph_backend_compare" 160 200 both  # a/160: 51,200
"$dir/sph_backend_compare" 320 100 cuda  # a/320: 204,800
