"""`frustum ... | head`: a reader that stops early ends the command quietly, as other command-line tools do."""

import os
import signal
import subprocess
import sys

LIST = "import sys; from pipeline.cli import main; sys.exit(main(['records', 'list']))"  # `frustum records list`


def test_a_closed_pipe_ends_the_command_without_a_traceback():
    read, write = os.pipe()
    os.close(read)  # the reader has gone before the first line is written (what `| head -0` does)
    try:
        done = subprocess.run([sys.executable, "-c", LIST], stdout=write, stderr=subprocess.PIPE, text=True,
                              timeout=120)
    finally:
        os.close(write)
    assert "Traceback" not in done.stderr and "BrokenPipeError" not in done.stderr, done.stderr
    assert done.returncode == 128 + signal.SIGPIPE
