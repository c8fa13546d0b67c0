#!/usr/bin/env bash
# Sourced by the benchmark scripts (jobs/bench_*.sh): prints what a number needs beside it to
# mean anything — the CPU (model, family/model as the kernel reads them, the widest vector ISA
# it offers), the cores this job may use, and the load average, at the start and (through
# `machine_load_at_end`, from an EXIT trap) at the end. A timing from a loaded machine is
# not a timing of the program; the load says how far to trust it.
cpu_field() { grep -m1 "^$1[[:space:]]*:" /proc/cpuinfo | sed 's/^[^:]*: *//'; }
machine_isa() {
  local flags
  flags=$(cpu_field flags)
  if [[ " $flags " == *" avx512f "* ]]; then echo "AVX-512"
  elif [[ " $flags " == *" avx2 "* ]]; then echo "AVX2"
  else echo "SSE2"; fi
}
echo "CPU: $(cpu_field 'model name') (vendor $(cpu_field vendor_id), family $(cpu_field 'cpu family'), model $(cpu_field model); widest ISA $(machine_isa)); cores usable: $(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc) (this process's affinity)"
echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
machine_load_at_end() { echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"; }
