"""What an end-to-end test in Python needs: checks that count their failures, and runs of the
program (under mpiexec for ranks > 0) whose exit code is checked, outputs read and compared."""
import os
import subprocess
import sys

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


def read(path, *names):
    """The named datasets of an output file, read whole."""
    with h5py.File(path) as f:
        return [f[n][()] for n in names]


class Runs:
    def __init__(self, binary, mpiexec, work, details=False, compare=None):
        self.binary, self.mpiexec, self.work = binary, mpiexec, work
        self.compare = compare  # tests/compare_outputs.py, for same_bits
        self.details = details  # print a check's detail when it passes too (measured values)
        self.failures = 0
        os.makedirs(work, exist_ok=True)
        os.environ.setdefault("CONTACTSWEEP_CACHE", os.path.join(work, "kernel_cache"))

    def check(self, name, ok, detail=""):
        shown = detail and (self.details or not ok)
        print(f"{'ok  ' if ok else 'FAIL'}  {name}" + (f": {detail}" if shown else ""))
        self.failures += not ok

    def launch(self, spec_text, name, *extra, ranks=0, threads=1, env_extra=None, quiet=True,
               expect=0):
        """launch() with its exit code checked against EXPECT (a failed check when it differs);
        returns the output's path (None when the exit code differs) and the finished process.
        An output left by an earlier run is removed first, so a refused run's "nothing written"
        can be seen."""
        out = os.path.join(self.work, name + ".h5")
        if os.path.exists(out):
            os.remove(out)
        out, result = launch(self.binary, self.mpiexec, self.work, spec_text, name, *extra,
                             ranks=ranks, threads=threads, env_extra=env_extra, quiet=quiet)
        if result.returncode != expect:
            self.check(f"{name} runs" if expect == 0 else f"{name} exits {expect}", False,
                       result.stderr.strip()[-2000:])
            return None, result
        return out, result

    def run(self, spec_text, name, *extra, ranks=0, threads=1):
        """The open output file of a run that exits 0, else None."""
        out, _ = self.launch(spec_text, name, *extra, ranks=ranks, threads=threads)
        return h5py.File(out, "r") if out else None

    def same_bits(self, name, *outputs, count=None):
        """Checks that the output files hold the same bits as the first (compare_outputs.py),
        and that there are COUNT of them when it is given (a failed run leaves one out)."""
        result = subprocess.run([sys.executable, self.compare, *outputs], capture_output=True,
                                text=True)
        self.check(name, (count is None or len(outputs) == count) and result.returncode == 0,
                   result.stdout[-1500:] + result.stderr[-500:])

    def finish(self):
        """The last line, and the exit code: 1 when any check failed."""
        print(f"{self.failures} check(s) failed" if self.failures else "all checks passed")
        sys.exit(1 if self.failures else 0)
