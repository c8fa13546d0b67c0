#!/usr/bin/python3
"""A finished block, the journal's manifest and the output survive a power cut once they carry
their final names: each is synced before the rename (or link) that names it, and the directory
that holds it after: the journal's after its manifest (with the output's directory, where the
journal was made) and before any block is named, again after every block before the output is
put in place, and the output's directory after the output's rename. A kill -9 cannot show a missing fsync (the page cache
keeps the data), so the real binary runs under strace and the order of its calls is checked.

  test_durability.py CONTACTSWEEP SPEC WORKDIR

Two runs: a fresh one (the output is linked in place: an output that appeared meanwhile is never
replaced) and a --force run over it (renamed in place). Exit 77 (skipped) without strace.
"""
import os
import re
import shutil
import subprocess
import sys

binary, spec, work = sys.argv[1:4]
if shutil.which("strace") is None:
    print("skip: strace is not installed")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
os.chdir(work)
work = os.getcwd()
args = ["--quiet", "--set", "grid.q_0.n=41", "--set", "grid.p_0.n=37",
        "--set", "integrator.t_end=10", "--set", "measures.final_state=true"]
failures = []


def fail(text):
    print("FAIL: " + text)
    failures.append(text)


# fsync(5</dir/name>), pwrite64(5</dir/name>, ...), renameat(3</dir>, "a", 3</dir>, "b"), link("a", "b"), rename("a", "b"),
# each possibly split by strace into "<unfinished ...>" and "<... resumed>" lines: the call is
# taken where it starts, which within its thread is before anything that follows it.
CALL = re.compile(r'^\d+ +(\w+)\((.*?)(?:\) += (-?\d+)| <unfinished \.\.\.>)')
FD_PATH = re.compile(r'^-?\d+<(.*?)>')


WRITES = ("write", "pwrite64", "writev", "pwritev", "pwritev2")
SYSCALLS = ("fsync", "fdatasync", "renameat", "renameat2", "rename", "link", "linkat") + WRITES


def calls(trace):
    out = []
    for line in open(trace):
        m = CALL.match(line)
        if not m or m.group(1) not in SYSCALLS:
            continue
        name, text = m.group(1), m.group(2)
        if name in ("fsync", "fdatasync") or name in WRITES:
            path = FD_PATH.match(text)
            out.append(("sync" if name not in WRITES else "write", path.group(1) if path else text))
        elif name in ("renameat", "renameat2", "linkat"):
            parts = re.findall(r'(?:-?\d+<(.*?)>|AT_FDCWD), "(.*?)"', text)
            absolute = [os.path.join(d or work, n) for d, n in parts[:2]]
            out.append(("name", absolute[0], absolute[1]))
        else:
            parts = re.findall(r'"(.*?)"', text)
            out.append(("name", os.path.join(work, parts[0]), os.path.join(work, parts[1])))
    return out


def check(run, extra):
    trace = run + ".trace"
    done = subprocess.run(["strace", "-f", "-y", "-qq", "-o", trace, "-e",
                           "trace=" + ",".join(SYSCALLS),
                           binary, "run", spec, "-o", "out.h5"] + args + extra,
                          env=dict(os.environ, OMP_NUM_THREADS="2"))
    if done.returncode != 0:
        fail(f"{run}: exit {done.returncode}")
        return
    journal = os.path.join(work, "out.h5.journal")
    output, partial = os.path.join(work, "out.h5"), os.path.join(work, "out.h5.partial")
    synced = set()
    blocks = manifests = 0
    placed = None
    unsynced_names = []  # journal entries named since the journal directory's last sync
    manifest_named_at = None
    for i, call in enumerate(calls(trace)):
        if call[0] == "sync":
            synced.add(call[1])
            if call[1] == journal:
                unsynced_names = []
            continue
        if call[0] == "write":  # written after its sync: the sync no longer covers it
            synced.discard(call[1])
            continue
        source, target = call[1], call[2]
        if os.path.dirname(target) == journal:
            if source not in synced:
                fail(f"{run}: {os.path.basename(target)} named before {source} was synced")
            synced.discard(source)  # the next write of this name must be synced again
            if os.path.basename(target).startswith("block_"):
                if blocks == 0 and manifest_named_at is not None:
                    between = [c[1] for c in calls(trace)[manifest_named_at:i] if c[0] == "sync"]
                    for directory in (journal, work) if extra == [] else (journal,):
                        if directory not in between:
                            fail(f"{run}: a block named before {directory} was synced after "
                                 f"the manifest's name")
                blocks += 1
            if os.path.basename(target) == "manifest":
                manifests += 1
                manifest_named_at = i
            unsynced_names.append(os.path.basename(target))
        elif target == output:
            if source != partial or partial not in synced:
                fail(f"{run}: the output named from {source} before it was synced")
            if unsynced_names:
                fail(f"{run}: the output put in place while the journal's directory was not "
                     f"synced after naming {unsynced_names[:3]}")
            placed = i
    if blocks == 0 or manifests != 1:
        fail(f"{run}: {blocks} blocks and {manifests} manifests journalled, expected some and 1")
    if placed is None:
        fail(f"{run}: the output was never put in place")
    else:
        after = [c for c in calls(trace)[placed + 1:] if c[0] == "sync"]
        if work not in [c[1] for c in after]:
            fail(f"{run}: the output's directory {work} was not synced after its rename")
    print(f"{run}: {blocks} blocks and the manifest synced after their last write and before "
          f"their rename, the journal's directory after them, the output likewise, its "
          f"directory after")


check("fresh", [])
if not os.path.exists("out.h5"):
    fail("fresh: no output")
check("force", ["--force"])
print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
