"""A handful of fuzzed record files through ``bearingfw record info`` as a user runs it (a subprocess):
an impossible file ends with exit status 2 and one line naming the file, never a traceback."""

from __future__ import annotations

import subprocess
import sys

import pytest
from fuzz_support import PROFILES, at2_files, column_files, fuzz_settings, junk_files
from hypothesis import given, note
from hypothesis import strategies as st

impossible_files = st.one_of(
    at2_files().filter(lambda drawn: drawn.expected is None),
    column_files().filter(lambda drawn: drawn.expected is None),
    junk_files(),
)


def options(drawn) -> list[str]:
    given = [(f"--{key}", value) for key, value in drawn.kwargs.items() if value is not None]
    return [f"{key}={value!r}" if key == "--dt" else f"{key}={value}" for key, value in given]


@pytest.mark.parametrize("profile", PROFILES)
def test_record_info_refuses_fuzzed_files_in_one_line(tmp_path, profile):
    @fuzz_settings(profile, scale=0.1)  # a subprocess each: 4 by default
    @given(impossible_files)
    def check(drawn):
        path = tmp_path / drawn.name
        path.write_bytes(drawn.content)
        files = [str(path)] * (3 if drawn.name.endswith(".AT2") else 1)  # three components: the reader decides
        note(f"{drawn.why}: {drawn.content[:300]!r}")
        done = subprocess.run([sys.executable, "-m", "bearingfw", "record", "info", *files, *options(drawn)],
                              capture_output=True, text=True, timeout=120)
        assert "Traceback" not in done.stderr, done.stderr
        if drawn.expected is ... and done.returncode == 0:  # junk that happens to be a record
            return
        assert done.returncode == 2, done.stderr
        lines = done.stderr.splitlines()
        assert len(lines) == 1 and lines[0].startswith("bearingfw record info: error: "), done.stderr
        assert path.name in lines[0]

    check()
