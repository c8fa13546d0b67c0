#!/usr/bin/env bash
# Accuracy charts: stability maps over h and work-precision (error against cost, per trajectory and
# per basin map) for every integrator; copies the PNGs into sweeps/figures/ (docs/methods.md,
# "Accuracy, cost and stability", quotes the numbers they print).
#   bash jobs/accuracy_charts.sh [--quick]
# Writes out/stability/ and out/work_precision/ (HDF5, work_precision.json, PNGs, and the printed
# tables in *.log). Runs from any directory; builds build/contactsweep if it is missing.
# Runtime on this project's machine (2 cores, shared): stability maps ~25 s, work-precision
# ~5 min (timing runs and basin maps on 1 thread, medians of 5); --quick: under a minute in all.
# Timings are taken with OMP_NUM_THREADS=1: run it on an otherwise idle machine.
# Environment: CONTACTSWEEP_BIN (default build/contactsweep, built if it is missing), FIGURES_DIR
# (default sweeps/figures).
set -euo pipefail
# Paths given in the environment are taken relative to the caller's directory.
bin=build/contactsweep figures=sweeps/figures
[[ -n ${CONTACTSWEEP_BIN:-} ]] && bin=$(realpath "$CONTACTSWEEP_BIN")
[[ -n ${FIGURES_DIR:-} ]] && figures=$(realpath -m "$FIGURES_DIR")
cd "$(dirname "${BASH_SOURCE[0]}")/.."
quick=()
[[ ${1:-} == --quick ]] && quick=(--quick)
if [[ $bin == build/contactsweep && ! -x $bin ]]; then
  [[ -f build/CMakeCache.txt ]] || cmake --preset release
  cmake --build --preset release
fi
py=/usr/bin/python3  # Debian's interpreter has numpy, xarray, h5netcdf, matplotlib
mkdir -p out/stability out/work_precision "$figures"
source jobs/machine_facts.sh  # the charts' ns/step are timings
trap machine_load_at_end EXIT

"$py" -B src/post/stability_maps.py --bin "$bin" --out out/stability "${quick[@]}" \
  | tee out/stability/stability_maps.log
"$py" -B src/post/work_precision.py --bin "$bin" --out out/work_precision "${quick[@]}" \
  | tee out/work_precision/work_precision.log

# --remove-destination: a name in the figures' directory is unlinked, then made anew (O_EXCL), never
# written through: a link another user left there (FIGURES_DIR in a shared place) would point
# cp at any file of yours. Their file or link in a sticky directory cannot be removed: cp stops,
# naming it.
cp --remove-destination out/stability/stability_h_gamma.png out/stability/stability_h_q0.png \
   out/work_precision/workprecision_damped_oscillator.png out/work_precision/workprecision_double_well.png \
   out/work_precision/basin_accuracy.png out/work_precision/basin_accuracy_magnetic_pendulum.png \
   "$figures"/
echo "charts copied to $figures/"
