"""The README's console examples print exactly what the README shows."""

import pathlib
import re
import shlex
import subprocess
import sys

README = pathlib.Path(__file__).resolve().parent.parent / "README.md"


def console_examples():
    text = README.read_text()
    for block in re.findall(r"```console\n(.*?)```", text, re.S):
        command, expected = None, []
        for line in block.splitlines():
            if line.startswith("$ "):
                if command:
                    yield command, expected
                command, expected = line[2:], []
            else:
                expected.append(line)
        if command:
            yield command, expected


def test_readme_console_output_is_current():
    examples = list(console_examples())
    assert len(examples) >= 2
    for command, expected in examples:
        args = shlex.split(command)
        assert args[0] == "linkage"
        r = subprocess.run([sys.executable, "-m", "sim", *args[1:]], capture_output=True, text=True)
        assert (r.stdout + r.stderr).splitlines() == expected, command
