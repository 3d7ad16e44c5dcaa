"""Defaults once: every default of every command (as `plumb COMMAND --help` shows it) against
its Python function's (the signature nanobind gives, __nb_signature__). Both front ends take
their defaults from the library (the option structs of include/plumb/*.h, a few constants
there); this catches a front end that writes its own, or a default one front end has and the
other does not."""

import re

import pytest

import plumb
from conftest import run_cli

FLAG = "<flag: off>"  # a CLI flag (--strict): off unless given
REQUIRED = "<required>"  # a Python argument without a default

# Which Python keyword each CLI option is, command by command. Every CLI option that shows a
# default (CLI11's "=VALUE" in --help) or is a flag must be here or in CLI_ONLY; every Python
# keyword whose default is not None must be here (as a value) or in PYTHON_ONLY. A tuple names
# keywords that together make the option's value (--size WIDTHxHEIGHT).
MAPPING = {
    "verify": {"--set": "set", "--keyframe": "keyframe", "--tol": "tol", "--until": "until"},
    "audit": {"--set": "set", "--keyframe": "keyframe", "--scenario": "scenario",
              "--strict": "strict", "--accept": "accept", "--repro": "repro"},
    "snapshot": {"--set": "set"},
    "diff": {"--set": "set", "--tol": "tol"},
    "run": {"--set": "set", "--keyframe": "keyframe", "--pose": "pose", "--qpos": "qpos",
            "--until": "until", "--every": "every", "--columns": "columns"},
    "inspect": {"--set": "set"},
    "converge": {"--set": "set", "--metric": "metric", "--dt": "dt", "--halvings": "halvings",
                 "--tol": "tol", "--until": "until"},
    "sweep": {"--set": "set", "--keyframe": "keyframe", "--pose": "pose", "--qpos": "qpos",
              "--vary": "vary", "--metric": "metrics", "--threads": "threads",
              "--until": "until", "--db": "db", "--resume": "resume"},
    "rollout": {"--set": "set", "--keyframe": "keyframe", "--pose": "pose", "--qpos": "qpos",
                "--until": "until", "--threads": "threads", "--seed": "seed",
                "--randomize": "randomize", "--ctrl-noise": "ctrl_noise", "--metric": "metrics",
                "--shard": "shard", "--db": "db", "--resume": "resume"},
    "render": {"--set": "set", "--keyframe": "keyframe", "--at": "at", "--until": "until",
               "--fps": "fps", "--camera": "camera", "--size": ("width", "height"),
               "--highlight": "highlight", "--msaa": "msaa", "--shadow-size": "shadow_size",
               "--gl": "gl", "--output": "output"},
    "replay": {"--set": "set", "--log": "log", "--columns": "columns", "--window": "window",
               "--input-delay": "input_delay", "--sensor-delay": "sensor_delay"},
    "identify": {"--set": "set", "--log": "log", "--fit": "fit", "--bounds": "bounds",
                 "--columns": "columns", "--window": "window", "--delay": "delay",
                 "--max-delay": "max_delay", "--validate": "validate", "--threads": "threads",
                 "--max-iterations": "max_iterations"},
}

# CLI options with a default and no Python keyword, and why ("*": every command).
CLI_ONLY = {
    "*": {
        "--format": "a Python call returns a result: .to_json(), repr(), .to_pandas() give "
                    "what --format chooses",
        "--all": "how much of the table the CLI prints; a Python result holds every row",
        "--quiet": "how much of the table the CLI prints; a Python result holds every row",
    },
    "rollout": {"--count": "plumb.rollout takes count as a required argument"},
}

# Python keywords with a default and no CLI option, and why.
PYTHON_ONLY = {}

# Defaults that differ on purpose, and why (the test fails when they come to agree, so that the
# entry goes).
DIFFERENT = {
    ("rollout", "--threads"): "the CLI runs one thread unless told (shared machines, job "
                              "arrays); in Python threads=0 uses every core (docs/python.md)",
    ("sweep", "--threads"): "as rollout's",
}

# Commands without a Python function, and Python functions without a command.
NO_BINDING = {
    "crosscheck": "runs a Python engine (MuJoCo Warp, MJX) in a process of its own",
    "bridge": "a long-running DDS process; its rehearsal (--client) is plumb.rehearse",
    "results": "a results store is read in Python with sqlite3 or plumb.Batch",
    "merge": "joins results stores, files on disk",
    "help": "the manual",
}
# (rehearse is `plumb bridge --client`; its first_command_timeout and grace are the library's
# RehearsalClient defaults)
NO_COMMAND = {"load", "mujoco_version", "compiled_mujoco_version", "mujoco_library", "rehearse"}


def cli_defaults(help_text: str) -> dict:
    """{option: its default as --help shows it, FLAG for a flag, None for none} of each option
    (its long name) under "Options:" of a command's --help."""
    out = {}
    section = None
    for line in help_text.splitlines():
        if line and not line.startswith(" "):
            section = line.strip()
            continue
        m = re.match(r"^  (-\S+)(.*)$", line)
        if section != "Options:" or not m:
            continue
        name = max(m.group(1).split(","), key=len)
        if name == "--help":
            continue
        spec = re.split(r"\s{2,}", m.group(2).strip())[0] if m.group(2).strip() else ""
        if not spec or not spec[0].isupper() or spec.startswith("Excludes"):
            out[name] = FLAG
        else:
            shown = re.search(r"=([^=\s\]}]+)$", spec.removesuffix(" REQUIRED"))
            out[name] = shown.group(1) if shown else None
    return out


def python_defaults(function) -> dict:
    """{keyword: its default, REQUIRED when it has none} of a nanobind function."""
    signature, _, defaults = function.__nb_signature__[0]
    start = signature.index("(") + 1
    depth, params, current = 0, [], ""
    for ch in signature[start:]:
        if ch in "[(":
            depth += 1
        elif ch in "])":
            if depth == 0:
                break
            depth -= 1
        if ch == "," and depth == 0:
            params.append(current.strip())
            current = ""
        else:
            current += ch
    params.append(current.strip())
    out = {}
    for param in params:
        if param in ("*", "/", "") or param.startswith("*"):  # render's *args (issue 49)
            continue
        name = re.match(r"\w+", param).group(0)
        index = re.search(r"= \\(\d+)$", param)
        out[name] = defaults[int(index.group(1))] if index else REQUIRED
    return out


def agree(cli_value, py_values) -> bool:
    """Whether a CLI option's default and the Python keywords' defaults say the same."""
    if len(py_values) == 2:  # --size WIDTHxHEIGHT
        return cli_value == "{}x{}".format(*py_values)
    value = py_values[0]
    python_has_none = value is None or value is REQUIRED
    if cli_value is None:
        return python_has_none
    if python_has_none:
        return False
    if cli_value is FLAG:
        return value is False
    if isinstance(value, bool):
        return False
    if isinstance(value, (int, float)):
        try:
            return float(cli_value) == float(value)
        except ValueError:
            return False
    return cli_value == str(value)


def mismatches(command, cli, py, mapping, cli_only, python_only, different) -> list:
    """Every way `cli` (cli_defaults) and `py` (python_defaults) of one command disagree."""
    problems = []
    excused = {**cli_only.get("*", {}), **cli_only.get(command, {})}
    for option, value in cli.items():
        if value is not None and option not in mapping and option not in excused:
            problems.append(f"plumb {command} {option} has a default ({value}) but no Python "
                            "keyword in MAPPING and no reason in CLI_ONLY")
    mapped = set()
    for option, keywords in mapping.items():
        keywords = keywords if isinstance(keywords, tuple) else (keywords,)
        mapped.update(keywords)
        if option not in cli:
            problems.append(f"MAPPING names {option}, not an option of plumb {command}")
            continue
        missing = [k for k in keywords if k not in py]
        if missing:
            problems.append(f"MAPPING names {missing}, not keywords of plumb.{command}")
            continue
        values = tuple(py[k] for k in keywords)
        same = agree(cli[option], values)
        shown = ", ".join(f"{k}={v!r}" for k, v in zip(keywords, values))
        if (command, option) in different:
            if same:
                problems.append(f"plumb {command} {option} and plumb.{command}({shown}) now "
                                "agree: remove the entry from DIFFERENT")
        elif not same:
            problems.append(f"plumb {command} {option} defaults to {cli[option]!r}, "
                            f"plumb.{command} to {shown}")
    for keyword, value in py.items():
        if value is not None and value is not REQUIRED and keyword not in mapped \
                and keyword not in python_only.get(command, {}):
            problems.append(f"plumb.{command}({keyword}={value!r}) has a default but no CLI "
                            "option in MAPPING and no reason in PYTHON_ONLY")
    return problems


def help_of(command: str) -> str:
    return run_cli(command, "--help", check_codes=(0,)).stdout


def test_every_command_and_every_function_is_listed():
    listed = run_cli("--help", check_codes=(0,)).stdout.split("Subcommands:")[1]
    commands = set(re.findall(r"^  ([a-z]+)\s{2,}", listed.split("\n\n")[0], re.M))
    assert commands == set(MAPPING) | set(NO_BINDING)
    functions = {name for name in dir(plumb) if not name.startswith("_")
                 and hasattr(getattr(plumb, name), "__nb_signature__")
                 and not isinstance(getattr(plumb, name), type)}
    assert functions == set(MAPPING) | NO_COMMAND


@pytest.mark.parametrize("command", sorted(MAPPING))
def test_the_defaults_agree(command):
    cli = cli_defaults(help_of(command))
    py = python_defaults(getattr(plumb, command))
    assert mismatches(command, cli, py, MAPPING[command], CLI_ONLY, PYTHON_ONLY,
                      DIFFERENT) == []


def test_the_help_and_the_signature_are_read():
    cli = cli_defaults(help_of("converge"))
    assert cli["--halvings"] == "4" and cli["--tol"] == "0.001" and cli["--dt"] is None
    assert cli_defaults(help_of("audit"))["--strict"] is FLAG
    assert cli_defaults(help_of("render"))["--size"] == "640x480"
    py = python_defaults(plumb.converge)
    assert py["model"] is REQUIRED and py["halvings"] == 4 and py["tol"] == 1e-3
    assert py["dt"] is None


PLANTED_HELP = """Options:
  -h,--help                   Print this help message and exit
  --tol FLOAT=0.01            relative tolerance
  --halvings INT:INT in [2 - 20]=4
                              number of halvings
  --strict                    exit 1 on warnings too
  --until FLOAT               run length
  --new INT=3                 a default added to the CLI alone
"""


def test_a_planted_mismatch_is_caught():
    cli = cli_defaults(PLANTED_HELP)
    assert cli == {"--tol": "0.01", "--halvings": "4", "--strict": FLAG, "--until": None,
                   "--new": "3"}
    mapping = {"--tol": "tol", "--halvings": "halvings", "--strict": "strict",
               "--until": "until"}
    py = {"model": REQUIRED, "tol": 1e-3, "halvings": 4, "strict": True, "until": 2.0,
          "extra": 7}
    found = mismatches("planted", cli, py, mapping, {}, {}, {})
    assert found == [
        "plumb planted --new has a default (3) but no Python keyword in MAPPING and no reason "
        "in CLI_ONLY",
        "plumb planted --tol defaults to '0.01', plumb.planted to tol=0.001",
        "plumb planted --strict defaults to '<flag: off>', plumb.planted to strict=True",
        "plumb planted --until defaults to None, plumb.planted to until=2.0",
        "plumb.planted(extra=7) has a default but no CLI option in MAPPING and no reason in "
        "PYTHON_ONLY",
    ]
    # the same pairs agreeing, with the CLI-only default given a reason: nothing is found
    py = {"model": REQUIRED, "tol": 0.01, "halvings": 4, "strict": False, "until": None}
    assert mismatches("planted", cli, py, mapping, {"planted": {"--new": "why"}}, {}, {}) == []
    # a difference listed as deliberate that is no longer one is found too
    stale = mismatches("planted", cli, py, mapping, {"*": {"--new": "why"}}, {},
                       {("planted", "--tol"): "why"})
    assert stale == ["plumb planted --tol and plumb.planted(tol=0.01) now agree: remove the "
                     "entry from DIFFERENT"]
    # a stale mapping entry (an option or keyword that went) is found
    assert mismatches("planted", cli, py, {**mapping, "--gone": "gone"},
                      {"*": {"--new": "why"}}, {}, {}) == [
        "MAPPING names --gone, not an option of plumb planted"]


def test_the_docs_name_every_command_without_a_function(root):
    # issue 49: docs/python.md said every command is a function; results and merge are not
    text = (root / "docs" / "python.md").read_text()
    assert "every command of the `plumb` tool as a" not in text
    section = text.split("## Commands without a function", 1)[1].split("\n## ", 1)[0]
    listed = set(re.findall(r"^\| `plumb ([a-z]+)` \|", section, re.M))
    assert listed == set(NO_BINDING) - {"help"}
