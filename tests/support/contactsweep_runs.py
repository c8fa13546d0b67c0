"""What an end-to-end test in Python needs: checks that count their failures, and runs of the
program (under mpiexec for ranks > 0) that return the open output file, None on failure."""
import os
import subprocess

import h5py


class Runs:
    def __init__(self, binary, mpiexec, work):
        self.binary, self.mpiexec, self.work = binary, mpiexec, work
        self.failures = 0
        os.makedirs(work, exist_ok=True)
        os.environ.setdefault("CONTACTSWEEP_CACHE", os.path.join(work, "kernel_cache"))

    def check(self, name, ok, detail=""):
        print(f"{'ok  ' if ok else 'FAIL'}  {name}" + (f": {detail}" if detail and not ok else ""))
        self.failures += not ok

    def run(self, spec_text, name, *extra, ranks=0, threads=1):
        spec = os.path.join(self.work, name + ".toml")
        out = os.path.join(self.work, name + ".h5")
        with open(spec, "w") as f:
            f.write(spec_text)
        command = [self.binary, "run", spec, "-o", out, "--force", "--quiet", *extra]
        env = dict(os.environ, OMP_NUM_THREADS=str(threads))
        if ranks:
            env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
            command = [self.mpiexec, "--oversubscribe", "-np", str(ranks), "--bind-to", "none"] + command
        result = subprocess.run(command, env=env, capture_output=True, text=True)
        if result.returncode != 0:
            self.check(f"{name} runs", False, result.stderr.strip()[-2000:])
            return None
        return h5py.File(out, "r")
