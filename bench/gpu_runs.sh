#!/usr/bin/env bash
# The GPU measurements of docs/performance.md, as run on a GPU machine (16 cores, one or
# more H100/H200). Expects the programs in $DEVICE_BIN (a folder holding dipc, bench_* and the GPU tests) and
# writes logs and CSVs into $OUT (default: bench/results/raw).
#
#   bench/gpu_runs.sh tests        GPU tests (element, contact and broad-phase kernels, GPU vs CPU trajectories on 1 rank,
#                                  and on 2 where there are two GPUs; GPU_TEST_RANKS, e.g. "1 2", chooses)
#   bench/gpu_runs.sh assembly     assembly throughput, GPU vs 16 CPU ranks
#   bench/gpu_runs.sh broadphase   contact broad phase, device vs one CPU core
#   bench/gpu_runs.sh crossover    seconds per Newton iteration, cpu vs cuda backend, 1 rank
#   bench/gpu_runs.sh host16       Newton breakdown on 16 ranks: CPU, and GPU assembly with host PETSc
#   bench/gpu_runs.sh device       Newton breakdown device-resident (needs the CUDA PETSc build)
#   bench/gpu_runs.sh weak         weak scaling 1 -> 2 -> 4 GPUs, WEAK_ELEMENTS (default 1000000) per GPU, each rank
#                                  bound to its share of the cores (CUDA PETSc build; WEAK_GPUS, default "1 2 4";
#                                  WEAK_STEPS, default 2)
#   bench/gpu_runs.sh mission      the 8000- and 64,000-hex block falling onto a plane, 1 GPU (CUDA PETSc build)
#   bench/gpu_runs.sh amgsweep     Newton breakdown device-resident under BoomerAMG/CG variants (CUDA PETSc build;
#                                  AMG_SIZES, default 1000000, per GPU; AMG_VARIANTS picks variants by name;
#                                  AMG_GPUS, e.g. "1 2", the GPU counts, default 1)
#   bench/gpu_runs.sh reuse        the same, 10 steps, AMG reuse (-dipc_pc_reuse) and looser CG (CUDA PETSc build)
#   bench/gpu_runs.sh presets      the same, 10 steps, each -dipc_preset and the built-in values before presets
#                                  (CUDA PETSc build; AMG_SIZES as for amgsweep)
#   bench/gpu_runs.sh strong       CPU strong scaling of whole steps on 1, 2, 4, 8, 16 ranks (STRONG_RANKS), 64,000
#                                  and 512,000 elements (STRONG_SIZES), with STRONG_THREADS OpenMP threads per rank
#                                  (default 1, dipc's setting; the cores' count is what the libraries take unset)
#   bench/gpu_runs.sh setup        time to the first Newton iteration (bench/setup.py), device-resident, on 1 GPU and,
#                                  where the machine has more, 4M elements on 4 ranks with METIS and RCB (CUDA PETSc build; SETUP_SIZES,
#                                  default 1000000,4000000; SETUP_BASE: another dipc, e.g. before a change, run too)
#   bench/gpu_runs.sh repro        every variant twice, 3 steps: do Newton and CG counts repeat? Candidates
#                                  for a reproducible device AMG (CUDA PETSc build; REPRO_SIZES, default
#                                  300000; AMG_VARIANTS picks variants by name)
#   bench/gpu_runs.sh census       CUDA runtime and MPI calls per rank (bench/cuda_call_census.c, CENSUS_LIB, default
#                                  $DEVICE_BIN/libcuda_call_census.so) in one step of a box of CENSUS_ELEMENTS (default
#                                  300000) per rank, on 1 and 2 ranks (sharing the GPU on a one-GPU host: the counts
#                                  compare, the seconds do not)
#   bench/gpu_runs.sh family       the contact-rich family (bench/contact_family.py: stack, squeeze, press), device-resident
#                                  on 1 GPU and on all CPU cores with a CPU build (FAMILY_CPU_DIPC, default
#                                  build/src/app/dipc: the CUDA PETSc's hypre runs on the GPU only); FAMILY_REFINE,
#                                  default 1,2,3,4 (about 0.1M, 1M, 3.4M, 8M hexes); FAMILY_STEPS, default 3;
#                                  FAMILY_MEMBERS, default stack,squeeze,press; FAMILY_EXTRA, more dipc options
#                                  (e.g. -log_view, which makes a GPU run call MPI_Allreduce ~44,000 times per step:
#                                  leave it out of multi-GPU timings); FAMILY_TAG, a suffix of the CSVs' tags; FAMILY_GPUS, the GPU
#                                  counts (default 1; e.g. "1 2 4", one rank per GPU); FAMILY_ELEMENTS, element
#                                  counts instead of refine levels; FAMILY_TIMEOUT, seconds per run; each run's
#                                  whole output is kept beside the CSV; FAMILY_OUTPUT=DIR keeps the runs' XDMF/HDF5
#   bench/gpu_runs.sh bigrun       one big contact-rich run on all the host's GPUs (issue 31): BIG_MEMBER (default
#                                  stack) scaled to BIG_ELEMENTS (default 20000000), BIG_STEPS (default 3), invariant
#                                  checks on, its output in $OUT/bigrun_output, a family CSV row (tag *_bigrun), and
#                                  the last step's surface per body (dipc-surface, where DEVICE_BIN has it) for
#                                  bench/render_surface.py; BIG_GPUS, BIG_EXTRA (more dipc options), BIG_TIMEOUT
#   bench/gpu_runs.sh amgstats     BoomerAMG's hierarchy (levels, rows and nonzeros per level, complexities) for
#                                  the stack at AMGSTATS_ELEMENTS (default 1000000) per GPU on 1 GPU and on all the
#                                  host's GPUs (AMGSTATS_GPUS), 2 steps: why a V-cycle costs 5x on 4 GPUs what it
#                                  costs on 1 (docs/performance.md, "Four H200s, measured"); summary in
#                                  $OUT/amgstats_summary.txt, each run's whole log beside it
set -uo pipefail
# Device-resident runs assemble straight into hypre's device matrix (-mat_type hypre) and run
# BoomerAMG there; -mat_type aijcusparse also works, but PCHYPRE then converts the matrix at every
# setup (8x slower per Newton iteration at 100K elements, README "GPU"). Override the matrix
# type with DEVICE_MAT and the preconditioner options with DEVICE_PC (e.g. "-pc_type gamg").
device_mat=${DEVICE_MAT:-hypre}
# The lent machines' Open MPI is not CUDA-aware: a CUDA PETSc refuses to start there without
# -use_gpu_aware_mpi 0. GPU_AWARE_MPI=1 leaves it out, for runs under a CUDA-aware MPI
# (scripts/build_cuda_aware_mpi.sh; the run header's "MPI" line says which path a run took).
staged=$([[ ${GPU_AWARE_MPI:-0} == 1 ]] || echo "-use_gpu_aware_mpi 0")
device_pc=${DEVICE_PC:-}
out=${OUT:-bench/results/raw}
mkdir -p "$out"
bin=${DEVICE_BIN:?source .device/activate first}
run() { echo "+ $*" >&2; "$@"; }
# combine_variants OUT amg_NAME.csv...: the CSVs' rows under one header, each prefixed by NAME.
combine_variants() {
  local target=$1; shift
  awk 'FNR == 1 { name = FILENAME; sub(/.*\/amg_/, "", name); sub(/\.csv$/, "", name) }
       FNR == 1 && !done { print "variant," $0; done = 1; next }
       FNR > 1 { print name "," $0 }' "$@" > "$target.tmp" && mv "$target.tmp" "$target"
}
# sweep TABLE STEPS "NAME|OPTIONS"...: one device-resident bench_step_breakdown per variant
# (AMG_VARIANTS picks some by name) and GPU count (AMG_GPUS, default 1; AMG_SIZES elements per
# GPU, each rank bound to its share of the cores; variants on n > 1 GPUs are named NAME_nGPU),
# then one table $out/TABLE.csv with the names in front.
sweep() {
  local table=$1 steps=$2 csvs=() v name n tag
  shift 2
  for v in "$@"; do
    name=${v%%|*}
    [[ -z "${AMG_VARIANTS:-}" || " $AMG_VARIANTS " == *" $name "* ]] || continue
    for n in ${AMG_GPUS:-1}; do
      [[ $n -le $gpus ]] || continue
      tag=$name$( ((n > 1)) && echo "_${n}gpu" )
      csvs+=("$out/amg_$tag.csv")
      run mpirun -n $n --map-by slot:PE=$(( $(nproc) / gpus )) "$bin/bench_step_breakdown" \
        -elements $((n * ${AMG_SIZES:-1000000})) -steps $steps -dipc_backend cuda -vec_type cuda -mat_type $device_mat \
        $staged ${v#*|} -csv "$out/amg_$tag.csv" | tail -2
    done
  done
  combine_variants "$out/$table.csv" "${csvs[@]}"
}
gpus=$(nvidia-smi -L | wc -l)
case "${1:-}" in
  tests)
    # Full output goes to $out/gpu_tests.log; the summary lines and exit codes to the screen.
    # The machine's Open MPI is not CUDA-aware: a CUDA PETSc refuses to start without
    # -use_gpu_aware_mpi 0 (exit 76). The trajectory tests read the scenes of this tree.
    export PETSC_OPTIONS="${PETSC_OPTIONS:-} $staged" DIPC_SOURCE_DIR=${DIPC_SOURCE_DIR:-$PWD}
    for t in element_kernels_gpu_tests contact_kernels_gpu_tests contact_form_gpu_tests contact_broad_phase_gpu_tests coo_reduction_gpu_tests direct_matrix_tests block_cache_gpu_tests; do
      run mpirun -n 1 "$bin/$t" --gtest_color=no 2>&1 | tee -a "$out/gpu_tests.log" |
        grep -E "^\[  (PASSED|FAILED|SKIPPED) |Failure" | tail -12
      echo "$t: exit ${PIPESTATUS[0]}"
    done
    # Two ranks on one GPU run about 13x slower than one (README, "Limits"): the 2-rank
    # trajectories took over 10 minutes on a one-GPU H200 host, so they run where there are two
    # GPUs, or when GPU_TEST_RANKS asks for them. Elsewhere two ranks share the GPU for the
    # short ones (ShortContactScenes), which reach the paths that only several ranks take.
    for n in ${GPU_TEST_RANKS:-$( ((gpus >= 2)) && echo 1 2 || echo 1 )}; do
      run mpirun -n $n "$bin/app_gpu_trajectory_tests" --gtest_color=no 2>&1 | tee -a "$out/gpu_tests.log" |
        grep -E "relative|FAIL|PASSED|SKIP|another rank"
      echo "app_gpu_trajectory_tests on $n ranks: exit ${PIPESTATUS[0]}"
    done
    if [[ -z ${GPU_TEST_RANKS:-} ]] && ((gpus < 2)); then
      run mpirun -n 2 "$bin/app_gpu_trajectory_tests" --gtest_color=no --gtest_filter='ShortContactScenes/*' 2>&1 |
        tee -a "$out/gpu_tests.log" | grep -E "relative|FAIL|PASSED|SKIP|another rank"
      echo "app_gpu_trajectory_tests ShortContactScenes on 2 ranks sharing the GPU: exit ${PIPESTATUS[0]}"
    fi ;;
  setup)
    device_opts=(-dipc_backend cuda -vec_type cuda -mat_type $device_mat $staged)
    # Each rank bound to its GPU's share of the cores, where the setup's host threads run.
    cores=$(( $(nproc) / gpus ))
    for d in ${SETUP_BASE:-} "$bin/dipc"; do
      card=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1 | awk '{print tolower($2)}')
      tag=${card}_$( [[ $d == "$bin/dipc" ]] && echo new || echo base )
      run python3 bench/setup.py --dipc "$d" --elements ${SETUP_SIZES:-1000000,4000000} --ranks 1 --partitioners metis \
        --cores-per-rank $cores --tag "$tag" --out "$out" --timeout 300 -- "${device_opts[@]}"
      if ((gpus >= 4)); then
        run python3 bench/setup.py --dipc "$d" --elements 4000000 --ranks 4 --partitioners metis,rcb \
          --cores-per-rank $cores --tag "${tag}_4gpu" --out "$out" --timeout 300 -- "${device_opts[@]}"
      fi
    done ;;
  census)
    for n in 1 2; do
      export CENSUS_FILE=$out/census_box_$n
      run mpirun -n $n -x LD_PRELOAD=${CENSUS_LIB:-$bin/libcuda_call_census.so} -x CENSUS_FILE \
        "$bin/bench_step_breakdown" -elements $((n * ${CENSUS_ELEMENTS:-300000})) -steps 1 -dipc_backend cuda -vec_type cuda \
        -mat_type $device_mat $staged $device_pc | tail -2
      grep -E "Memcpy|Malloc|Free|Synchronize|MPI_(Allreduce|Waitall)" "$out/census_box_$n.0"
    done ;;
  family)
    card=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1 | awk '{print tolower($2)}')
    members=${FAMILY_MEMBERS:-stack,squeeze,press}
    # The rank gets the cores of its GPU's share of the host for its host threads (mpirun alone
    # binds one rank to one core).
    # FAMILY_ELEMENTS (approximate element counts, e.g. 20000000) replaces the refine levels.
    sizes=(--refine ${FAMILY_REFINE:-1,2,3,4})
    [[ -n ${FAMILY_ELEMENTS:-} ]] && sizes=(--elements $FAMILY_ELEMENTS)
    # FAMILY_GPUS (e.g. "1 2 4") runs the same sizes on one rank per GPU for each count the
    # host has; each rank keeps its GPU's share of the cores.
    keep=()
    [[ -n ${FAMILY_OUTPUT:-} ]] && keep=(--keep-output "$FAMILY_OUTPUT")
    for n in ${FAMILY_GPUS:-1}; do
      ((n <= gpus)) || continue
      run python3 bench/contact_family.py --dipc "$bin/dipc" --members $members "${sizes[@]}" "${keep[@]}" \
        --steps ${FAMILY_STEPS:-3} --ranks $n --cores-per-rank $(( $(nproc) / gpus )) --tag "${card}_${n}gpu${FAMILY_TAG:-}" \
        --out "$out" --timeout ${FAMILY_TIMEOUT:-1800} -- -dipc_backend cuda -vec_type cuda \
        -mat_type $device_mat $staged $device_pc ${FAMILY_EXTRA:-}
    done
    cpu_dipc=${FAMILY_CPU_DIPC:-build/src/app/dipc}
    if [[ -x $cpu_dipc ]]; then
      run python3 bench/contact_family.py --dipc "$cpu_dipc" --members $members "${sizes[@]}" \
        --steps ${FAMILY_STEPS:-3} --ranks $(nproc) --tag "${card}_host_cpu$(nproc)${FAMILY_TAG:-}" --out "$out" -- -dipc_backend cpu \
        ${FAMILY_EXTRA:-}
    else
      echo "family: no CPU build at $cpu_dipc (FAMILY_CPU_DIPC): CPU runs skipped" >&2
    fi ;;
  bigrun)
    # The 20.1M-hex stack on 4 H200s took 16 s to its first step and 171 s for 3 steps with its
    # output (docs/performance.md, "Four H200s, measured"); the surface files are a few per cent
    # of the output, small enough to copy off the machine.
    big_out=$out/bigrun_output
    FAMILY_MEMBERS=${BIG_MEMBER:-stack} FAMILY_ELEMENTS=${BIG_ELEMENTS:-20000000} FAMILY_GPUS=${BIG_GPUS:-$gpus} \
      FAMILY_STEPS=${BIG_STEPS:-3} FAMILY_CPU_DIPC=/nonexistent FAMILY_TAG=_bigrun FAMILY_OUTPUT=$big_out \
      FAMILY_TIMEOUT=${BIG_TIMEOUT:-1800} FAMILY_EXTRA="-dipc_check_invariants ${BIG_EXTRA:-}" bash "$0" family
    for h5 in "$big_out"/*/*.h5; do
      [[ -e $h5 && $h5 != *checkpoint* ]] || continue
      if [[ -x $bin/dipc-surface ]]; then
        run "$bin/dipc-surface" "$h5" "$out/$(basename "$(dirname "$h5")")_surface.vtp" --split-bodies
      else
        echo "bigrun: no dipc-surface in $bin: no surface written" >&2
      fi
    done ;;
  amgstats)
    for n in ${AMGSTATS_GPUS:-1 $gpus}; do
      FAMILY_MEMBERS=stack FAMILY_ELEMENTS=$((n * ${AMGSTATS_ELEMENTS:-1000000})) FAMILY_GPUS=$n FAMILY_STEPS=2 \
        FAMILY_CPU_DIPC=/nonexistent FAMILY_TAG=_amgstats FAMILY_TIMEOUT=${AMGSTATS_TIMEOUT:-300} \
        FAMILY_EXTRA="-pc_hypre_boomeramg_print_statistics 1" bash "$0" family
    done
    # hypre prints one table per setup; the first setup of each run (its levels' rows and
    # nonzeros, and the complexities) goes into the summary.
    for log in "$out"/contact_family_*_amgstats_stack_*.log; do
      echo "== $log"
      awk '/BoomerAMG SETUP PARAMETERS/ { n++ } n == 1' "$log" |
        grep -E "Num MPI tasks|Num levels|^ *[0-9]+ +[0-9]+ +[0-9]+ |Complexity|operator =|memory =" | head -40
    done > "$out/amgstats_summary.txt"
    cat "$out/amgstats_summary.txt" ;;
  assembly)
    run mpirun -n 16 "$bin/bench_assembly_throughput" -sizes 10000,100000,1000000,4000000 -repeat 5 \
      -csv "$out/assembly_throughput.csv" ;;
  broadphase)
    run "$bin/bench_broad_phase" -triangles 10000,100000,1000000 -repeat 5 -csv "$out/broad_phase.csv" ;;
  crossover)
    for be in cpu cuda; do
      run mpirun -n 1 "$bin/bench_step_breakdown" -elements 500,1000,2500,5000,20000 -steps 2 -dipc_backend $be \
        -csv "$out/crossover_$be.csv" | tail -6
    done ;;
  strong)
    threads=${STRONG_THREADS:-1}
    csvs=()
    for r in ${STRONG_RANKS:-1 2 4 8 16}; do
      csvs+=("$out/strong_t${threads}_r$r.csv")
      OMP_NUM_THREADS=$threads run mpirun -n $r -x OMP_NUM_THREADS "$bin/bench_step_breakdown" \
        -elements ${STRONG_SIZES:-64000,512000} -steps 2 -dipc_backend cpu -csv "$out/strong_t${threads}_r$r.csv" | tail -3
    done
    awk 'FNR == 1 && NR > 1 { next } { print }' "${csvs[@]}" > "$out/strong_scaling_t$threads.csv" ;;
  host16)
    for be in cpu cuda; do
      run mpirun -n 16 "$bin/bench_step_breakdown" -elements 100000,1000000 -steps 2 -dipc_backend $be \
        -csv "$out/breakdown_host16_$be.csv" | tail -3
    done ;;
  device)
    run mpirun -n 1 "$bin/bench_step_breakdown" -elements 100000,1000000 -steps 2 -dipc_backend cuda \
      -vec_type cuda -mat_type $device_mat $staged $device_pc -csv "$out/breakdown_device.csv" | tail -3 ;;
  weak)
    for n in ${WEAK_GPUS:-1 2 4}; do
      [[ $n -le $gpus ]] || continue
      run mpirun -n $n --map-by slot:PE=$(( $(nproc) / gpus )) "$bin/bench_step_breakdown" \
        -elements $((n * ${WEAK_ELEMENTS:-1000000})) -steps ${WEAK_STEPS:-2} -dipc_backend cuda \
        -vec_type cuda -mat_type $device_mat $staged $device_pc -csv "$out/weak_$n.csv" | tail -2
    done ;;
  mission)
    for r in 1 2; do
      run mpirun -n 1 "$bin/dipc" scenes/block_on_plane.json -dipc_refine $r -dipc_backend cuda -vec_type cuda \
        -mat_type $device_mat $staged $device_pc -dipc_no_output | tail -26
    done ;;
  amgsweep)
    # Each variant: a name and the options it adds to the defaults of newton_solver.cpp.
    variants=(
      "default|"
      "aggressive|-pc_hypre_boomeramg_agg_nl 1"
      "theta07|-pc_hypre_boomeramg_strong_threshold 0.7"
      "keeptranspose|-pc_hypre_boomeramg_keeptranspose 1"
      "agg_theta07_pmax2|-pc_hypre_boomeramg_agg_nl 1 -pc_hypre_boomeramg_strong_threshold 0.7 -pc_hypre_boomeramg_P_max 2"
      "ew|-snes_ksp_ew"
      "agg_lag3|-pc_hypre_boomeramg_agg_nl 1 -snes_lag_preconditioner 3 -snes_lag_preconditioner_persists"
      "agg_kt|-pc_hypre_boomeramg_agg_nl 1 -pc_hypre_boomeramg_keeptranspose 1"
      "agg_kt_lag3|-pc_hypre_boomeramg_agg_nl 1 -pc_hypre_boomeramg_keeptranspose 1 -snes_lag_preconditioner 3 -snes_lag_preconditioner_persists"
      "agg_kt_lag3_rtol4|-pc_hypre_boomeramg_agg_nl 1 -pc_hypre_boomeramg_keeptranspose 1 -snes_lag_preconditioner 3 -snes_lag_preconditioner_persists -ksp_rtol 1e-4"
      # Chebyshev smoothing: no inner products, fewer synchronisations per V-cycle level on
      # several GPUs, where the CG iteration grows 1.3-1.7x from 1 to 2 (docs/performance.md).
      "cheby|-pc_hypre_boomeramg_relax_type_all Chebyshev"
      # Fewer or thinner coarse levels: each level of a V-cycle makes about five halo exchanges on
      # several GPUs, each a synchronisation, whatever the level's size (docs/performance.md).
      "maxlev6|-pc_hypre_boomeramg_max_levels 6"
      "pmax2|-pc_hypre_boomeramg_P_max 2"
    )
    sweep amg_sweep 2 "${variants[@]}" ;;
  reuse)
    # The AMG hierarchy kept while it pays (-dipc_pc_reuse) and looser CG, over 10 steps so that
    # reuse across steps counts (README "GPU"); AMG_SIZES and AMG_VARIANTS as for amgsweep.
    sweep amg_reuse ${REUSE_STEPS:-10} "default|" "reuse|-dipc_pc_reuse" "reuse_rtol4|-dipc_pc_reuse -ksp_rtol 1e-4" \
      "reuse_rtol3|-dipc_pc_reuse -ksp_rtol 1e-3" ;;
  presets)
    # What each preset costs per Newton iteration on the device (bench_step_breakdown applies
    # -dipc_preset as dipc does, balanced without it): the issue-12 target is <= 0.2 s per
    # Newton iteration for the default at 1M elements on one H100. "builtin" names the values
    # dipc had before presets (0.665 s there, bench/results/amg_reuse_count_rule_h100_1m.csv).
    sweep presets ${REUSE_STEPS:-10} "builtin|-dipc_velocity_tol_rel 1e-5 -ksp_rtol 1e-8 -dipc_pc_reuse 0" \
      "fast|-dipc_preset fast" "balanced|" "accurate|-dipc_preset accurate" ;;
  repro)
    # Two runs of each variant; "same" when Newton and CG counts repeat (the CPU runs repeat bit for
    # bit, app_default_reproducible_tests). dipc's device gradient kernels add element and contact
    # contributions with atomicAdd (element_kernels.cu, contact_kernels.cu), whose order varies, so
    # "cpu_assembly" (host assembly, device matrix and AMG) separates dipc's part from hypre's; the
    # rest are hypre switches that PETSc reaches (README "Speed or accuracy", reproducibility).
    variants=(
      "balanced|"
      "cpu_assembly|-dipc_backend cpu"
      "keept|-pc_hypre_boomeramg_keeptranspose 1"
      "spgemm_cusparse|-pc_mg_galerkin_mat_product_algorithm cusparse"
      "keept_spgemm_cusparse|-pc_hypre_boomeramg_keeptranspose 1 -pc_mg_galerkin_mat_product_algorithm cusparse"
      "cpu_assembly_keept_cusparse|-dipc_backend cpu -pc_hypre_boomeramg_keeptranspose 1 -pc_mg_galerkin_mat_product_algorithm cusparse"
    )
    AMG_SIZES=${REPRO_SIZES:-300000}
    for rep in 1 2; do sweep repro_$rep ${REPRO_STEPS:-3} "${variants[@]}"; done
    # Compare the two runs of each variant: Newton and CG counts, and the time per Newton iteration.
    awk -F, 'NR == FNR && FNR > 1 { n[$1] = $8; k[$1] = $9; t[$1] = $19; next }
             FNR > 1 { printf "%-30s newton %s/%s ksp %s/%s %s  s/newton %s %s\n", $1, n[$1], $8, k[$1], $9,
                       (n[$1] == $8 && k[$1] == $9) ? "same" : "DIFFER", t[$1], $19 }' \
      "$out/repro_1.csv" "$out/repro_2.csv" | tee "$out/repro_summary.txt"
    # The per-variant CSVs are in repro_1/2.csv now (and the device tool returns at most 8 files).
    for v in "${variants[@]}"; do rm -f "$out/amg_${v%%|*}.csv"; done ;;
  *) sed -n '2,/^set -uo/p' "$0" | sed '$d'; exit 2 ;;
esac
