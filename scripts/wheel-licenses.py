#!/usr/bin/env python3
"""Lists every library auditwheel bundled into plumb's wheel, with its licence, in the wheel.

Usage: wheel-licenses.py REPAIRED_WHEEL LICENCE_TABLE OUT_FOLDER

For each file in the wheel's plumb_mujoco.libs/ it finds the system library it was copied from
(the file of that name, through ldconfig), that library's Debian package and source package
(dpkg), and the source package's licence in LICENCE_TABLE (python/bundled-licenses.toml:
reviewed by hand, one [packages.<source>] entry per source package). It then writes, into the wheel's
.dist-info/licenses/:
  THIRD-PARTY.md                  the table: bundled file, Debian package and version, licence
  debian/<source>.copyright       each package's full copyright file from /usr/share/doc
adds a License-File line for each to METADATA, and packs the wheel again into OUT_FOLDER
(`wheel pack` writes RECORD anew).

A bundled library whose source package the table does not list stops the build (exit 1),
naming it: a new dependency's licence is reviewed before a wheel carries it.
"""

import functools
import pathlib
import re
import subprocess
import sys
import tempfile
import tomllib


def run(*args: str) -> str:
    return subprocess.run(args, check=True, capture_output=True, text=True).stdout


@functools.cache
def system_libraries() -> list[pathlib.Path]:
    """The x86-64 libraries ldconfig knows, read once."""
    paths = []
    for line in run("ldconfig", "-p").splitlines():
        fields = line.strip().split(" => ")
        if len(fields) == 2 and "x86-64" in fields[0]:
            paths.append(pathlib.Path(fields[1]))
    return paths


def system_library(name: str) -> pathlib.Path:
    """The system library auditwheel copied: it keeps the file's name, with a hash added."""
    for path in system_libraries():
        if path.resolve().name == name or path.name == name:
            return path
    sys.exit(f"wheel-licenses.py: {name} (bundled by auditwheel) is not a system library "
             "ldconfig knows: cannot tell its package")


def debian_package(library: pathlib.Path) -> tuple[str, str, str]:
    """(binary package, source package, version) that installed library."""
    real = library.resolve()
    candidates = [real, library]
    for path in list(candidates):  # merged /usr: dpkg records a path as its package ships it
        text = str(path)
        if text.startswith("/usr/lib/"):
            candidates.append(pathlib.Path(text[4:]))
        elif text.startswith("/lib/"):
            candidates.append(pathlib.Path("/usr" + text))
    for path in candidates:
        found = subprocess.run(["dpkg", "-S", str(path)], capture_output=True, text=True)
        if found.returncode == 0:
            package = found.stdout.split(":")[0].strip()
            source, version = run("dpkg-query", "-W", "-f", "${source:Package}\t${Version}",
                                  package).split("\t")
            return package, source, version
    sys.exit(f"wheel-licenses.py: no Debian package owns {library} ({real}): cannot tell its "
             "licence")


def main() -> None:
    if len(sys.argv) != 4:
        sys.exit(__doc__.strip().splitlines()[2])
    wheel, table_file, out = (pathlib.Path(a) for a in sys.argv[1:])
    with open(table_file, "rb") as f:
        table = tomllib.load(f)
    with tempfile.TemporaryDirectory() as tmp:
        run(sys.executable, "-m", "wheel", "unpack", "-d", tmp, str(wheel))
        (root,) = pathlib.Path(tmp).iterdir()
        (info,) = root.glob("*.dist-info")
        libs = sorted((root / "plumb_mujoco.libs").glob("*.so*"))
        licences = info / "licenses"
        (licences / "debian").mkdir(parents=True, exist_ok=True)
        rows, files, unknown = [], [], []
        for lib in libs:
            original = re.sub(r"-[0-9a-f]{8}(?=\.so)", "", lib.name)
            package, source, version = debian_package(system_library(original))
            entry = table["packages"].get(source)
            if entry is None:
                unknown.append(f"{lib.name} ({original}, Debian package {package}, source {source})")
                continue
            copyright_file = f"debian/{source}.copyright"
            if not (licences / copyright_file).exists():
                doc = pathlib.Path("/usr/share/doc") / package / "copyright"
                (licences / copyright_file).write_bytes(doc.read_bytes())
                files.append(copyright_file)
            note = entry.get("note", "")
            rows.append(f"| `{lib.name}` | `{original}` | {package} {version} ({source}) | "
                        f"{entry['license']} | {note} |")
        if unknown:
            sys.exit("wheel-licenses.py: the wheel bundles libraries whose licence "
                     f"{table_file} does not list: " + "; ".join(unknown) + ". Review each "
                     "source package's /usr/share/doc/<package>/copyright and add it.")
        (licences / "THIRD-PARTY.md").write_text(
            "# Libraries bundled in this wheel\n\n" + table["preamble"].strip() + "\n\n"
            "| file in plumb_mujoco.libs/ | copied from | Debian package (source) | licence | note |\n"
            "|---|---|---|---|---|\n" + "\n".join(rows) + "\n\nThe full copyright file of each "
            "source package is in debian/ beside this file.\n")
        files.insert(0, "THIRD-PARTY.md")
        metadata = info / "METADATA"
        text = metadata.read_text()
        head, sep, body = text.partition("\n\n")
        head += "".join(f"\nLicense-File: {name}" for name in files)
        metadata.write_text(head + sep + body)
        out.mkdir(parents=True, exist_ok=True)
        run(sys.executable, "-m", "wheel", "pack", "-d", str(out), str(root))
    print(f"{len(libs)} bundled libraries from {len(files) - 1} source packages listed")


if __name__ == "__main__":
    main()
