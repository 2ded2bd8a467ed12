#!/usr/bin/env bash
# The GPU measurements of bench/README.md, as run on the lent GPU machine (16 cores, one or
# more H100/H200). Expects the programs in $DEVICE_BIN (../shared/device/pack + activate) and
# writes logs and CSVs into $OUT (default: bench/results/raw).
#
#   bench/gpu_runs.sh tests        GPU tests (element kernels, GPU vs CPU trajectories, 1 and 2 ranks)
#   bench/gpu_runs.sh assembly     assembly throughput, GPU vs 16 CPU ranks
#   bench/gpu_runs.sh crossover    seconds per Newton iteration, cpu vs cuda backend, 1 rank
#   bench/gpu_runs.sh host16       Newton breakdown on 16 ranks: CPU, and GPU assembly with host PETSc
#   bench/gpu_runs.sh device       Newton breakdown device-resident (needs the CUDA PETSc build)
#   bench/gpu_runs.sh weak         weak scaling 1 -> 2 -> 4 GPUs, 1M elements per GPU (CUDA PETSc build)
set -uo pipefail
# Device-resident runs use GAMG: with the CUDA PETSc 3.22.5 + hypre 2.32 of ../shared/gpu-stack,
# converting dipc's COO-assembled aijcusparse matrix to hypre fails on the device ("CUDA ERROR
# invalid argument at memory.c:803", README "GPU"). Override with DEVICE_PC="...".
# GAMG's Galerkin products (MatPtAP) run on the host (-matptap_backend_cpu): on the device,
# cuSPARSE ran out of resources for them at 1M elements on a 141 GB H200.
device_pc=${DEVICE_PC:--pc_type gamg -matptap_backend_cpu}
out=${OUT:-bench/results/raw}
mkdir -p "$out"
bin=${DEVICE_BIN:?source .device/activate first}
run() { echo "+ $*" >&2; "$@"; }
gpus=$(nvidia-smi -L | wc -l)
case "${1:-}" in
  tests)
    for t in element_kernels_gpu_tests contact_kernels_gpu_tests contact_form_gpu_tests; do
      run mpirun -n 1 "$bin/$t" --gtest_color=no 2>&1 | grep -E "^\[  (PASSED|FAILED|  OK) |FAILED|Failure" | tail -12
    done
    for n in 1 2; do
      run mpirun -n $n "$bin/app_gpu_trajectory_tests" --gtest_color=no 2>&1 | grep -E "relative|OK|FAIL|PASSED|SKIP|another rank"
      echo "app_gpu_trajectory_tests on $n ranks: exit ${PIPESTATUS[0]}"
    done ;;
  assembly)
    run mpirun -n 16 "$bin/bench_assembly_throughput" -sizes 10000,100000,1000000,4000000 -repeat 5 \
      -csv "$out/assembly_throughput.csv" ;;
  crossover)
    for be in cpu cuda; do
      run mpirun -n 1 "$bin/bench_step_breakdown" -elements 500,1000,2500,5000,20000 -steps 2 -dipc_backend $be \
        -csv "$out/crossover_$be.csv" | tail -6
    done ;;
  host16)
    for be in cpu cuda; do
      run mpirun -n 16 "$bin/bench_step_breakdown" -elements 100000,1000000 -steps 2 -dipc_backend $be \
        -csv "$out/breakdown_host16_$be.csv" | tail -3
    done ;;
  device)
    run mpirun -n 1 "$bin/bench_step_breakdown" -elements 100000,1000000 -steps 2 -dipc_backend cuda \
      -vec_type cuda -mat_type aijcusparse -use_gpu_aware_mpi 0 $device_pc -csv "$out/breakdown_device.csv" | tail -3 ;;
  weak)
    for n in ${WEAK_GPUS:-1 2 4}; do
      [[ $n -le $gpus ]] || continue
      run mpirun -n $n "$bin/bench_step_breakdown" -elements $((n * 1000000)) -steps 2 -dipc_backend cuda \
        -vec_type cuda -mat_type aijcusparse -use_gpu_aware_mpi 0 $device_pc -csv "$out/weak_$n.csv" | tail -2
    done ;;
  *) sed -n '2,14p' "$0"; exit 2 ;;
esac
