"""What an end-to-end test in Python needs: checks that count their failures, and runs of the
program (under mpiexec for ranks > 0) that return the open output file, None on failure."""
import os
import subprocess

import h5py


def launch(binary, mpiexec, work, spec_text, name, *extra, ranks=0, threads=1, env_extra=None,
           quiet=True):
    """Writes the spec as WORK/NAME.toml and runs it into WORK/NAME.h5 (under mpiexec, as root
    if need be, for ranks > 0); returns the output's path and the finished process."""
    spec = os.path.join(work, name + ".toml")
    out = os.path.join(work, name + ".h5")
    with open(spec, "w") as f:
        f.write(spec_text)
    command = [binary, "run", spec, "-o", out, "--force", *(["--quiet"] if quiet else []), *extra]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), **(env_extra or {}))
    if ranks:
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        command = [mpiexec, "--oversubscribe", "-np", str(ranks), "--bind-to", "none"] + command
    return out, subprocess.run(command, env=env, capture_output=True, text=True)


class Runs:
    def __init__(self, binary, mpiexec, work, details=False):
        self.binary, self.mpiexec, self.work = binary, mpiexec, work
        self.details = details  # print a check's detail when it passes too (measured values)
        self.failures = 0
        os.makedirs(work, exist_ok=True)
        os.environ.setdefault("CONTACTSWEEP_CACHE", os.path.join(work, "kernel_cache"))

    def check(self, name, ok, detail=""):
        shown = detail and (self.details or not ok)
        print(f"{'ok  ' if ok else 'FAIL'}  {name}" + (f": {detail}" if shown else ""))
        self.failures += not ok

    def run(self, spec_text, name, *extra, ranks=0, threads=1):
        out, result = launch(self.binary, self.mpiexec, self.work, spec_text, name, *extra,
                             ranks=ranks, threads=threads)
        if result.returncode != 0:
            self.check(f"{name} runs", False, result.stderr.strip()[-2000:])
            return None
        return h5py.File(out, "r")
