#!/usr/bin/env bash
# Build a CUDA-aware Open MPI 4.1.4 from Debian bookworm's own source package (openmpi 4.1.4-3)
# and install it into a self-contained, relocatable prefix.
#
#   scripts/build_cuda_aware_mpi.sh [PREFIX] [WORKDIR]
#       PREFIX   install prefix            (default /opt/ompi-cuda)
#       WORKDIR  scratch dir for the build (default $WORKDIR or /tmp/ompi-cuda-build)
#
# Why: dipc links Debian's Open MPI (libmpi.so.40, through PETSc), which is NOT CUDA-aware, so
# MPI calls must not be given device pointers. This script builds the very same Open MPI version
# (same sonames: libmpi.so.40, libmpi_cxx.so.40, libmpi_mpifh.so.40, ...) with CUDA support. An
# unchanged dipc binary then picks it up at run time, no relinking:
#
#   export OPAL_PREFIX=$PREFIX PATH=$PREFIX/bin:$PATH LD_LIBRARY_PATH=$PREFIX/lib:${LD_LIBRARY_PATH:-}
#   mpirun -np 2 build/src/app/dipc ...
#
# The prefix carries its own hwloc, libevent and PMIx (Open MPI's internal copies), so it only
# needs glibc, libstdc++, libgfortran5 and zlib on the target. No GPU is needed to build: Open MPI
# 4.1 compiles against cuda.h only and dlopen()s the driver's libcuda.so.1 at run time. To move
# it to another machine: tar it (done at the end, see TARBALL), unpack anywhere, set OPAL_PREFIX.
#
# Environment knobs: CUDA_HOME (default /usr/local/cuda), JOBS (default 2), TARBALL (default
# /tmp/ompi-cuda.tar.xz, empty = no tarball), OMPI_FORTRAN (default mpifh, see step 3),
# SKIP_BUILD=1 (only run the checks of step 5 on an existing PREFIX).
# Needs root (apt-get, writing PREFIX) and Debian 12. Takes ~10 min on 2 cores (make ~4 min).
set -euo pipefail

PREFIX=${1:-/opt/ompi-cuda}
WORKDIR=${2:-${WORKDIR:-/tmp/ompi-cuda-build}}
CUDA_HOME=${CUDA_HOME:-/usr/local/cuda}
JOBS=${JOBS:-2}
TARBALL=${TARBALL-/tmp/ompi-cuda.tar.xz}
OMPI_FORTRAN=${OMPI_FORTRAN:-mpifh}
SKIP_BUILD=${SKIP_BUILD:-0}
DEB_VERSION=4.1.4-3                       # the source version behind Debian's 4.1.4-3+b1 binaries
SCRIPT_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
PATCH_DIR=$SCRIPT_DIR/patches             # our own patches (only if the build needs them)

PREFIX=$(realpath -m "$PREFIX")
WORKDIR=$(realpath -m "$WORKDIR")
SRC=$WORKDIR/openmpi-4.1.4                # unpacked Debian source tree (Debian patches applied)
BUILD=$WORKDIR/build                      # out-of-tree build dir
LOG=$WORKDIR/logs
t0=$SECONDS
step() { printf '\n=== [%s, +%ds] %s\n' "$(date +%T)" $((SECONDS - t0)) "$*"; }
die()  { echo "ERROR: $*" >&2; exit 1; }

[[ $(id -u) == 0 ]] || die "run as root (apt-get, writes $PREFIX)"
[[ -f $CUDA_HOME/include/cuda.h ]] || die "$CUDA_HOME/include/cuda.h not found (set CUDA_HOME)"
[[ $PREFIX != / && $PREFIX != /usr && $PREFIX != /usr/local ]] || die "refusing PREFIX=$PREFIX"
mkdir -p "$WORKDIR" "$LOG"

if [[ $SKIP_BUILD != 1 ]]; then
# --- 1. source package and build tools ------------------------------------------------------
# debian.sources only lists binary ("deb") archives. Add a temporary "deb-src" entry with the
# same mirror and key, and remove it again on exit (even on failure), then refresh apt's lists.
step "1. fetch Debian source package openmpi=$DEB_VERSION"
SRC_LIST=/etc/apt/sources.list.d/zz-ompi-cuda-tmp-deb-src.sources
MIRROR=$(awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
MIRROR=${MIRROR:-http://deb.debian.org/debian}
cleanup_apt() { rm -f "$SRC_LIST"; apt-get update -qq >/dev/null 2>&1 || true; }
trap cleanup_apt EXIT
cat >"$SRC_LIST" <<EOF
Types: deb-src
URIs: $MIRROR
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
apt-get update -qq
# Build tools: compilers (gfortran only for the mpif.h bindings, see step 3), autotools+libtool
# (Debian's patches touch configure.ac/Makefile.am, so the build system must be regenerated
# exactly as debian/rules does), flex (Build-Depends), zlib (Debian's libopen-rte uses it).
apt-get install -y -qq --no-install-recommends \
  build-essential gfortran perl flex autoconf automake libtool m4 pkg-config zlib1g-dev \
  dpkg-dev xz-utils file >/dev/null
rm -rf "$SRC" "$BUILD" "$WORKDIR"/openmpi_*
# apt-get source downloads .dsc/.orig/.debian tarballs (checked against the signed Release file)
# and unpacks them with dpkg-source, which applies debian/patches/*. No other source is used.
if ! (cd "$WORKDIR" && apt-get source --only-source "openmpi=$DEB_VERSION") >"$LOG/apt-source.log" 2>&1; then
  cat "$LOG/apt-source.log" >&2
  die "apt-get source openmpi=$DEB_VERSION failed (error above); not trying any other source"
fi
grep -E '^dpkg-source: info: applying' "$LOG/apt-source.log" | sed 's/^/  /'
cleanup_apt; trap - EXIT

# Our own patches, if any (e.g. for CUDA 13 API changes), kept in scripts/patches/.
shopt -s nullglob
for p in "$PATCH_DIR"/openmpi-4.1.4-*.diff; do
  echo "  applying $(basename "$p")"; patch -d "$SRC" -p1 --forward <"$p"
done
shopt -u nullglob

# --- 2. regenerate the build system, as debian/rules (override_dh_update_autotools_config) -----
step "2. autogen.pl --force (as debian/rules does)"
(cd "$SRC/config" && autom4te --language=m4sh opal_get_version.m4sh -o opal_get_version.sh)
(cd "$SRC" && nice -n 10 ./autogen.pl --force) >"$LOG/autogen.log" 2>&1 \
  || { tail -40 "$LOG/autogen.log"; die "autogen failed, see $LOG/autogen.log"; }

# --- 3. configure ---------------------------------------------------------------------------
# ABI: same version/sonames as Debian; C++ bindings (libmpi_cxx.so.40, dipc links it) and the
# MPI extensions Debian ships (affinity, cuda, pcollreq = MPIX_*_init symbols) are kept.
# OMPI_FORTRAN=mpifh builds only the mpif.h bindings (libmpi_mpifh.so.40), not the slow
# "use mpi"/"use mpi_f08" modules: PETSc links libmpi_mpifh.so.40, and PETSc uses Fortran
# datatypes (MPI_INTEGER, MPI_DOUBLE_PRECISION, ...) which a --disable-mpi-fortran libmpi
# leaves unusable. OMPI_FORTRAN=no gives --disable-mpi-fortran (then Debian's libmpi_mpifh
# would be mixed in at run time: not recommended).
# Self-contained: internal hwloc/libevent/PMIx; no UCX/verbs/OFI/PSM (those would need the
# target's own libucx/libibverbs/...: intra-node transport is the smcuda/vader BTLs, inter-node
# is TCP, with device buffers staged through host memory). reachable-netlink is left out as it
# needs libnl-3 (the built-in "weighted" component does the same job without it).
# Relocatable: no rpath in the wrapper compilers (LD_LIBRARY_PATH is used), sysconfdir under
# PREFIX, so OPAL_PREFIX moves everything.
step "3. configure (CUDA: $CUDA_HOME)"
if [[ $OMPI_FORTRAN == no ]]; then fortran_flag=--disable-mpi-fortran; else fortran_flag=--enable-mpi-fortran=$OMPI_FORTRAN; fi
CONFIG_FLAGS=(
  --prefix="$PREFIX"
  --with-cuda="$CUDA_HOME"
  --enable-mpi-ext=affinity,cuda,pcollreq
  --enable-mpi-cxx
  "$fortran_flag"
  --disable-oshmem --disable-mpi-java
  --enable-shared --disable-static
  --with-hwloc=internal --with-libevent=internal --with-pmix=internal
  --without-ucx --without-verbs --without-ofi --without-psm --without-psm2
  --without-tm
  --enable-mca-no-build=reachable-netlink
  --enable-ipv6
  --disable-wrapper-rpath --disable-wrapper-runpath
  --with-package-string="Open MPI 4.1.4 (Debian source 4.1.4-3, CUDA-aware)"
)
printf '  %s\n' "${CONFIG_FLAGS[@]}"
mkdir -p "$BUILD"
# HOSTNAME/USER are baked into ompi_info output; neutral values, as debian/rules does.
(cd "$BUILD" && HOSTNAME=hostname USER=username nice -n 10 "$SRC/configure" "${CONFIG_FLAGS[@]}") \
  >"$LOG/configure.log" 2>&1 || { tail -40 "$LOG/configure.log"; die "configure failed, see $LOG/configure.log"; }
sed -n '/^Open MPI configuration:/,$p' "$LOG/configure.log" | grep -E 'CUDA|Fort mpif|C\+\+|Version|PMIx|hwloc|libevent' | sed 's/^/  /' || true

# --- 4. build and install ---------------------------------------------------------------------
# nice: leave CPU to other work on the machine. install-strip strips binaries and libraries.
step "4. make -j$JOBS (log: $LOG/make.log)"
tb=$SECONDS
(cd "$BUILD" && nice -n 10 make -j"$JOBS") >"$LOG/make.log" 2>&1 \
  || { grep -nE 'error|Error' "$LOG/make.log" | tail -20; die "make failed, see $LOG/make.log"; }
echo "  make took $(( (SECONDS - tb) / 60 )) min $(( (SECONDS - tb) % 60 )) s"
rm -rf "$PREFIX"
(cd "$BUILD" && make install-strip) >"$LOG/install.log" 2>&1 \
  || { tail -30 "$LOG/install.log"; die "make install failed, see $LOG/install.log"; }
# Not needed at run time or to compile: man pages, docs, libtool .la files (absolute paths).
rm -rf "$PREFIX/share/man" "$PREFIX/share/doc"
find "$PREFIX" -name '*.la' -delete
fi  # SKIP_BUILD

# --- 5. checks --------------------------------------------------------------------------------
step "5. checks"
[[ -x $PREFIX/bin/mpirun ]] || die "$PREFIX/bin/mpirun missing"
NEWENV=(env PATH="$PREFIX/bin:$PATH" LD_LIBRARY_PATH="$PREFIX/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" OPAL_PREFIX="$PREFIX")
DEBENV=(env -u OPAL_PREFIX)  # Debian's own tools must not see OPAL_PREFIX (they would look there)
MPIRUN_ARGS=(--allow-run-as-root --oversubscribe -np 2)
# Without an NVIDIA driver (no libcuda.so.1, e.g. on this build host) Open MPI warns at MPI_Init
# that it cannot dlopen libcuda.so.1 and then runs without device-pointer support; silence that.
if ! ldconfig -p | grep 'libcuda\.so\.1 ' >/dev/null; then
  echo "  (no libcuda.so.1 here: setting OMPI_MCA_opal_warn_on_missing_libcuda=0 for the checks)"
  export OMPI_MCA_opal_warn_on_missing_libcuda=0
fi
T=$WORKDIR/checks; rm -rf "$T"; mkdir -p "$T"

echo "--- 5a. ompi_info: built with CUDA?"
info=$("${NEWENV[@]}" ompi_info --parsable --all)
grep -E 'mpi_built_with_cuda_support:value|^ompi:version:full|bindings:(c|cxx|mpif.h):' <<<"$info"
grep -q 'mpi_built_with_cuda_support:value:true' <<<"$info" || die "not CUDA-aware"

# One program for all runs: prints MPIX_Query_cuda_support() (a compile-time constant in 4.1.4:
# 1 = library built CUDA-aware, regardless of GPU/driver presence) and reduces with a Fortran
# datatype (as PETSc does) to check those are usable.
cat >"$T/hello.c" <<'EOF'
#include <mpi.h>
#include <mpi-ext.h>   /* MPIX_Query_cuda_support, MPIX_CUDA_AWARE_SUPPORT */
#include <stdio.h>
int main(int argc, char **argv) {
  int rank, size, one = 1, sum = 0; char lib[MPI_MAX_LIBRARY_VERSION_STRING]; int len;
  MPI_Init(&argc, &argv); MPI_Comm_rank(MPI_COMM_WORLD, &rank); MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Allreduce(&one, &sum, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD);   /* Fortran type from C */
  MPI_Get_library_version(lib, &len);
  if (rank == 0) printf("hello: size=%d allreduce(MPI_INTEGER)=%d MPIX_Query_cuda_support()=%d lib=%.34s\n",
                        size, sum, MPIX_Query_cuda_support(), lib);
  MPI_Finalize(); return 0; }
EOF

echo "--- 5b. compile with NEW mpicc, run 2 ranks with NEW mpirun"
"${NEWENV[@]}" mpicc "$T/hello.c" -o "$T/hello_new"
"${NEWENV[@]}" mpirun "${MPIRUN_ARGS[@]}" "$T/hello_new"
grep -rh '^#define MPIX_CUDA_AWARE_SUPPORT' "$PREFIX/include" || true

echo "--- 5c. ABI: binary built with DEBIAN's mpicc, run on the NEW library"
if [[ -x /usr/bin/mpicc.openmpi ]]; then
  "${DEBENV[@]}" /usr/bin/mpicc.openmpi "$T/hello.c" -o "$T/hello_debian"
  echo "  with Debian's library:"; "${DEBENV[@]}" /usr/bin/mpirun.openmpi "${MPIRUN_ARGS[@]}" "$T/hello_debian"
  echo "  with the new library (LD_LIBRARY_PATH=$PREFIX/lib):"
  "${NEWENV[@]}" ldd "$T/hello_debian" | grep -E 'libmpi|libopen-(pal|rte)'
  "${NEWENV[@]}" mpirun "${MPIRUN_ARGS[@]}" "$T/hello_debian"
  # Same for a PETSc program (PETSc pulls libmpi_mpifh/libmpi_cxx from Debian, like dipc).
  PETSC_DIR=/usr/lib/petscdir/petsc3.18/x86_64-linux-gnu-real
  if [[ -f $PETSC_DIR/include/petsc.h ]]; then
    cat >"$T/petsc_vec.c" <<'EOF'
#include <petscvec.h>
int main(int argc, char **argv) {
  Vec x; PetscReal nrm; PetscInt n; PetscMPIInt size;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(VecCreateMPI(PETSC_COMM_WORLD, 1000, PETSC_DETERMINE, &x));
  PetscCall(VecSet(x, 2.0)); PetscCall(VecNorm(x, NORM_1, &nrm)); PetscCall(VecGetSize(x, &n));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "petsc: ranks=%d n=%d |x|_1=%g (expect %g)\n", size, (int)n, (double)nrm, 2.0 * n));
  PetscCall(VecDestroy(&x)); PetscCall(PetscFinalize()); return 0; }
EOF
    "${DEBENV[@]}" /usr/bin/mpicc.openmpi -I"$PETSC_DIR/include" "$T/petsc_vec.c" -o "$T/petsc_vec" \
      -L"$PETSC_DIR/lib" -Wl,-rpath,"$PETSC_DIR/lib" -lpetsc_real
    "${NEWENV[@]}" ldd "$T/petsc_vec" | grep -E 'libmpi|libopen-(pal|rte)|hwloc|libevent|pmix'
    "${NEWENV[@]}" mpirun "${MPIRUN_ARGS[@]}" "$T/petsc_vec"
  fi
else
  echo "  (Debian's libopenmpi-dev not installed: skipped)"
fi

echo "--- 5d. exported MPI symbols missing vs Debian's libraries (should be none)"
for l in libmpi.so.40 libmpi_cxx.so.40 libmpi_mpifh.so.40; do
  deb=/usr/lib/x86_64-linux-gnu/$l
  [[ -e $deb && -e $PREFIX/lib/$l ]] || { echo "  $l: not compared (missing here or there)"; continue; }
  syms() { nm -D --defined-only "$1" | awk '{print $3}' | grep -E '^(P?MPIX?_|ompi_mpi_|_ZN3MPI|mpi_|MPI_|pmpi_)' | sort -u; }
  missing=$(comm -23 <(syms "$deb") <(syms "$PREFIX/lib/$l") | wc -l)
  echo "  $l: $(syms "$deb" | wc -l) Debian symbols, $missing missing in new"
done

echo "--- 5e. self-contained: libraries the install needs from the system"
needed=$(find "$PREFIX" -type f \( -name '*.so*' -o -perm -u+x \) -exec sh -c 'file -b "$1" | grep -q ELF' _ {} \; -print \
  | xargs -r readelf -d 2>/dev/null | awk '/NEEDED/ {gsub(/[][]/, "", $5); print $5}' | sort -u)
echo "  " $needed
# allowed: glibc/gcc runtime, zlib, and the install's own libraries
extra=$(grep -vE '^(libc|libm|libdl|libpthread|librt|libutil|libgcc_s|libstdc\+\+|libgfortran|libquadmath|libz|ld-linux.*)\.so|^(libmpi|libmpi_cxx|libmpi_mpifh|libopen-pal|libopen-rte|libmca_common_[a-z]+)\.so' <<<"$needed" || true)
[[ -z $extra ]] || die "install needs other system libraries: $extra"
if find "$PREFIX" -name '*.so*' -type f | xargs -r env LD_LIBRARY_PATH="$PREFIX/lib" ldd 2>/dev/null | grep 'not found'; then
  die "unresolved libraries"
fi

echo "--- 5f. relocation: copy the tree elsewhere, hide the original, run with OPAL_PREFIX"
RELOC=$WORKDIR/reloc/$(basename "$PREFIX"); rm -rf "$WORKDIR/reloc"; mkdir -p "$WORKDIR/reloc"
cp -a "$PREFIX" "$RELOC"
mv "$PREFIX" "$PREFIX.hidden-for-reloc-test"
trap 'mv "$PREFIX.hidden-for-reloc-test" "$PREFIX"' EXIT
env PATH="$RELOC/bin:$PATH" LD_LIBRARY_PATH="$RELOC/lib" OPAL_PREFIX="$RELOC" \
  ompi_info --parsable --all | grep -E 'mpi_built_with_cuda_support:value|^path:prefix:'
env PATH="$RELOC/bin:$PATH" LD_LIBRARY_PATH="$RELOC/lib" OPAL_PREFIX="$RELOC" \
  mpicc "$T/hello.c" -o "$T/hello_reloc"
env PATH="$RELOC/bin:$PATH" LD_LIBRARY_PATH="$RELOC/lib" OPAL_PREFIX="$RELOC" \
  mpirun "${MPIRUN_ARGS[@]}" "$T/hello_reloc"
mv "$PREFIX.hidden-for-reloc-test" "$PREFIX"; trap - EXIT
rm -rf "$WORKDIR/reloc"

# --- 6. sizes and tarball -------------------------------------------------------------------
step "6. sizes"
du -sh "$PREFIX"
if [[ -n $TARBALL ]]; then
  XZ_OPT=-9e tar -C "$(dirname "$PREFIX")" -cJf "$TARBALL" "$(basename "$PREFIX")"
  ls -l "$TARBALL" | awk '{printf "  %s: %d bytes (%.1f MiB)\n", $9, $5, $5/1048576}'
  echo "  on the target: tar -C /opt -xJf $(basename "$TARBALL"); then set OPAL_PREFIX, PATH, LD_LIBRARY_PATH as above"
fi
step "done: $PREFIX"
