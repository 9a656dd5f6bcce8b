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


def test_readme_slider_crank_example_is_the_shipped_file():
    text = README.read_text()
    block = re.search(r"```toml\n(format = \"linkage/1\"\nname = \"slider_crank\".*?)```", text, re.S).group(1)
    shipped = (README.parent / "analytic" / "library" / "slider_crank.toml").read_text()
    assert block == shipped


def test_readme_links_resolve_inside_the_repository():
    # the README stands on its own: every relative link and picture exists in a clone
    text = README.read_text()
    for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", text):
        if not target.startswith(("http://", "https://")):
            assert (README.parent / target).exists(), target
