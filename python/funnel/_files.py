"""Writing output files safely: checked before any work, written through a temporary file.

Every picture, animation and page the package writes goes through :func:`replacing`: the data
goes to a temporary file beside the target, which is renamed onto it only when complete and is
removed on any failure, so that neither a partial file nor a stray temporary is ever left.
"""

from __future__ import annotations

import argparse
import contextlib
import os
from pathlib import Path


class OneLineParser(argparse.ArgumentParser):
    """The package's command lines: an error is one line naming what is wrong, then where the
    options are listed, with exit status 2, as `funnel`'s own (argparse printed its whole usage
    block first)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\nRun '{self.prog} --help' for its options.\n")


VALID_OUT = "valid values are a file path in an existing, writable directory"


def check_output(out, what="out"):
    """Raises ValueError, before any work, if ``out`` cannot be written: a directory, or a path
    whose directory is missing or not writable (the command line's rules, docs/cli.md)."""
    out = Path(out)
    if out.is_dir():
        raise ValueError(f"invalid {what} = '{out}': is a directory; {VALID_OUT}")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"invalid {what} = '{out}': directory '{parent}' does not exist; {VALID_OUT}")
    if not os.access(parent, os.W_OK):
        raise ValueError(f"invalid {what} = '{out}': directory '{parent}' is not writable; {VALID_OUT}")
    if out.exists() and not os.access(out, os.W_OK):
        raise ValueError(f"invalid {what} = '{out}': is not writable; {VALID_OUT}")


@contextlib.contextmanager
def replacing(out, hidden=True):
    """Yields a temporary path beside ``out`` (``.NAME.tmp.SUFFIX``, or ``NAME.tmp.SUFFIX`` with
    hidden=False) to write to; renames it onto ``out`` when the block ends normally, removes it
    otherwise."""
    out = Path(out)
    check_output(out)
    name = f".{out.name}.tmp{out.suffix}" if hidden else f"{out.stem}.tmp{out.suffix}"
    tmp = out.with_name(name)
    try:
        yield tmp
        os.replace(tmp, out)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
