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


NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def same_printout(got: str, want: str) -> bool:
    """The words match exactly and every number within one unit of its last printed digit (the README
    prints 5-6 significant digits; a value within rounding of a digit boundary may print either way on
    another machine's libm)."""
    if NUMBER.sub("#", got) != NUMBER.sub("#", want):
        return False
    for g, w in zip(NUMBER.findall(got), NUMBER.findall(want)):
        digits = w.lstrip("+-").split("e")[0].split("E")[0]
        decimals = len(digits.split(".")[1]) if "." in digits else 0
        exponent = int(re.split("[eE]", w)[1]) if re.search("[eE]", w) else 0
        if abs(float(g) - float(w)) > 10.0 ** (exponent - decimals) * 1.000001:
            return False
    return True


def test_same_printout_tells_digits_from_words():
    assert same_printout("x 0.624999 .. 1.4599 m", "x 0.625000 .. 1.4600 m")
    assert not same_printout("x 0.624990 m", "x 0.625000 m")
    assert not same_printout("x 0.625 mm", "x 0.625 m")
    assert not same_printout("K = 2.7350", "K = 2.7352")


def test_readme_console_output_is_current():
    examples = list(console_examples())
    assert len(examples) >= 2
    for command, expected in examples:
        args = shlex.split(command)
        assert args[0] == "linkage"
        r = subprocess.run([sys.executable, "-m", "sim", *args[1:]], capture_output=True, text=True)
        got = (r.stdout + r.stderr).splitlines()
        assert len(got) == len(expected), command
        for g, w in zip(got, expected):
            assert same_printout(g, w), (command, g, w)


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


def test_readme_python_script_prints_what_the_readme_shows(tmp_path, monkeypatch, capsys):
    """The README's Python API script, run as written, prints its text block (numbers to their digits)."""
    text = README.read_text()
    section = text.split("## Python API", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    expected = re.search(r"```text\n(.*?)```", section, re.S).group(1).splitlines()
    monkeypatch.chdir(tmp_path)                        # a script writes nothing, and reads nothing from here
    exec(compile(code, "README.md (Python API)", "exec"), {"__name__": "__readme__"})
    got = capsys.readouterr().out.splitlines()
    assert len(got) == len(expected), got
    for g, w in zip(got, expected):
        assert same_printout(g, w), (g, w)
