#!/usr/bin/python3
"""Writing the post-processing scripts' outputs (figures, a spec, a JSON summary) without
following a link or writing through another user's file.

Outputs often go to shared places (/tmp, a group-writable project directory): opening the name,
as savefig(path) or Path.write_text do, would follow a link planted there and overwrite whatever
it points to with our permissions. Instead each output is written to a new temporary file of its
own in the same directory and renamed over the name: rename replaces a link, never its target.
"""
import os
import stat
import sys
import tempfile
from pathlib import Path


def write_output(path, write, text=False):
    """Call write(f) on a new file and put it at path; exits naming path if that fails."""
    path = Path(path)
    try:
        if stat.S_ISDIR(os.lstat(path).st_mode):  # lstat: a link to a directory is just replaced
            sys.exit(f"cannot write {path}: it is a directory")
    except FileNotFoundError:
        pass
    tmp = None
    try:
        # mkstemp: O_EXCL | O_NOFOLLOW, mode 0600, a random name retried until it is new, so
        # nothing planted in the directory is ever opened; the leading dot keeps it out of globs
        # like *.png.
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
        with os.fdopen(fd, "w" if text else "wb") as f:
            write(f)
            # As a file created by name would be (mkstemp made it 0600): the umask decides.
            os.fchmod(f.fileno(), 0o666 & ~_umask())
        os.replace(tmp, path)  # rename(2): the name is replaced, a link at it is not followed
    except BaseException as e:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except FileNotFoundError:
                pass
        if isinstance(e, OSError):
            sys.exit(f"cannot write {path}: {e.strerror or e}")
        raise


def save_figure(fig, path, **kwargs):
    """fig.savefig(path, **kwargs) through write_output; the format is path's suffix, as
    savefig would infer it from the name."""
    path = Path(path)
    write_output(path, lambda f: fig.savefig(f, format=path.suffix[1:].lower(), **kwargs))


def write_text(path, text):
    """Path(path).write_text(text) through write_output."""
    write_output(path, lambda f: f.write(text), text=True)


def _umask():
    mask = os.umask(0o022)  # read only by setting it; set straight back (the scripts are serial)
    os.umask(mask)
    return mask
