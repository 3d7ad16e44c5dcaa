#!/usr/bin/env python3
"""Hostile models: mutates real MJCF models and runs every mutant through plumb.

Each mutant (an attribute set to NaN, negative, zero or huge; an element deleted or
duplicated; a reference to a name that does not exist; a mesh, texture or include file
missing; the file truncated at a random point; an include cycle; or two of these at once)
goes through `plumb inspect`, `verify`, `audit` and `snapshot -o`, each under a time
limit. A mutant must end with a clear error or a finding: exit 0, 1 (a check failed, with
its findings on stdout), 2 (bad input, one `plumb:` paragraph on stderr), 3 (diverged) or
4 (MuJoCo's fatal error, reported by plumb). A crash (a signal), a hang (the time limit),
an internal error (70), a sanitizer report, a MuJoCo log file (MuJoCo's own handler ran,
which may call exit()), a half-written snapshot or an exit 1 without findings is a defect:
the mutant is kept in FAILURES/ with the command that broke on it.

Usage:
  hostile_models.py --plumb PLUMB [--seed N] [--count N] [--timeout S (240)] [--jobs N]
                    [--sample N] [--json FILE] [--failures DIR] [--robot-corpus] ROOT...
ROOT is a model file or a folder searched for whole MJCF models (a <mujoco> file with a
<worldbody>); --sample N draws N of them from each ROOT that has more.

Exit codes: 0 every mutant ended cleanly, 1 at least one defect, 2 bad usage (no models).
Only the Python standard library is used.
"""

import argparse
import collections
import concurrent.futures
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

COMMANDS = (
    ("inspect", ["inspect", "{model}"]),
    ("verify", ["verify", "{model}", "--quiet"]),
    ("audit", ["audit", "{model}"]),
    ("snapshot", ["snapshot", "{model}", "-o", "{out}"]),
)
CLEAN_EXITS = {0, 1, 2, 3, 4}
# Attributes that name another element of the model.
REFERENCES = {
    "joint", "joint1", "joint2", "body", "body1", "body2", "geom", "geom1", "geom2",
    "site", "site1", "site2", "tendon", "tendon1", "tendon2", "class", "childclass",
    "material", "mesh", "texture", "hfield", "target", "objname", "refname", "actuator",
    "jointinparent", "cranksite", "slidersite", "camera", "light", "key",
}
FILE_ATTRS = ("file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback")
VALUES = ("nan", "-nan", "inf", "-inf", "0", "-1", "1e300", "-1e300", "1e-300", "-{v}",
          "{v}e30")


def find_models(root, sample, rng):
    """MJCF files under root (a file, or a folder of models); `sample` of them when given."""
    if os.path.isfile(root):
        return [root]
    found = []
    for folder, _, files in os.walk(root):
        for name in sorted(files):
            if not name.endswith(".xml"):
                continue
            path = os.path.join(folder, name)
            try:
                with open(path, encoding="utf-8", errors="replace") as f:
                    head = f.read(4096)
            except OSError:
                continue
            # whole models only: included fragments (<mujocoinclude>, assets) are not run alone
            if re.search(r"<mujoco[\s>]", head) and "<worldbody" in open(
                    path, encoding="utf-8", errors="replace").read():
                found.append(path)
    found.sort()
    if sample and len(found) > sample:
        found = sorted(rng.sample(found, sample))
    return found


def mirror(model, work):
    """A mirror of the model's folder in `work`, files as symlinks, so mutants sit beside
    the original and every relative asset path still resolves. Returns the folder."""
    source = os.path.dirname(os.path.abspath(model))
    dest = os.path.join(work, "m%d" % len(os.listdir(work)))
    for folder, dirs, files in os.walk(source):
        rel = os.path.relpath(folder, source)
        os.makedirs(os.path.join(dest, rel), exist_ok=True)
        for name in files:
            os.symlink(os.path.join(folder, name), os.path.join(dest, rel, name))
    return dest


# ---- mutations: each takes (tree root, text, rng, ctx) and returns new text or None ----------

def elements(root):
    return [e for e in root.iter() if e is not root]


def numeric_attribute(root, rng, _ctx):
    candidates = []
    for e in root.iter():
        for k, v in e.attrib.items():
            if re.fullmatch(r"\s*[-+0-9.eE]+(\s+[-+0-9.eE]+)*\s*", v):
                candidates.append((e, k, v))
    if not candidates:
        return None
    e, k, v = rng.choice(candidates)
    numbers = v.split()
    i = rng.randrange(len(numbers))
    numbers[i] = rng.choice(VALUES).format(v=numbers[i].lstrip("-+"))
    e.set(k, " ".join(numbers))
    return "%s.%s=%s" % (e.tag, k, e.get(k))


def delete_element(root, rng, _ctx):
    parents = [(p, c) for p in root.iter() for c in list(p)]
    if not parents:
        return None
    p, c = rng.choice(parents)
    p.remove(c)
    return "deleted <%s%s>" % (c.tag, " name=%s" % c.get("name") if c.get("name") else "")


def duplicate_element(root, rng, _ctx):
    parents = [(p, c) for p in root.iter() for c in list(p)]
    if not parents:
        return None
    p, c = rng.choice(parents)
    p.insert(list(p).index(c) + 1, ET.fromstring(ET.tostring(c)))
    return "duplicated <%s%s>" % (c.tag, " name=%s" % c.get("name") if c.get("name") else "")


def dangling_reference(root, rng, _ctx):
    candidates = [(e, k) for e in root.iter() for k in e.attrib if k in REFERENCES]
    if not candidates:
        return None
    e, k = rng.choice(candidates)
    e.set(k, "no_such_%s_%d" % (k, rng.randrange(1000)))
    return "%s.%s -> %s" % (e.tag, k, e.get(k))


def missing_file(root, rng, ctx):
    candidates = [(e, k) for e in root.iter() for k in e.attrib if k in FILE_ATTRS]
    if not candidates:
        return None
    e, k = rng.choice(candidates)
    if rng.random() < 0.5:
        e.set(k, "missing/" + os.path.basename(e.get(k)))
        return "%s.%s names a file that does not exist" % (e.tag, k)
    # the file itself gone (from the mirror: a symlink, restored after this mutant)
    folder = ctx["folder"]
    for base in (folder, os.path.join(folder, ctx.get("meshdir", "")),
                 os.path.join(folder, ctx.get("texturedir", ""))):
        path = os.path.normpath(os.path.join(base, e.get(k)))
        if os.path.islink(path) and path.startswith(ctx["work"]):
            ctx["removed"].append((path, os.readlink(path)))
            os.unlink(path)
            return "%s %s deleted" % (e.tag, e.get(k))
    e.set(k, "missing/" + os.path.basename(e.get(k)))
    return "%s.%s names a file that does not exist" % (e.tag, k)


def include_cycle(root, rng, ctx):
    name = os.path.basename(ctx["mutant"])
    if rng.random() < 0.5:
        root.insert(0, ET.Element("include", file=name))
        return "includes itself"
    other = ctx["mutant"] + ".inc.xml"
    with open(other, "w") as f:
        f.write('<mujoco><include file="%s"/></mujoco>\n' % name)
    ctx["extra"].append(other)
    root.insert(0, ET.Element("include", file=os.path.basename(other)))
    return "includes a file that includes it back"


TREE_MUTATIONS = {
    "attribute": numeric_attribute,
    "delete": delete_element,
    "duplicate": duplicate_element,
    "reference": dangling_reference,
    "missing-file": missing_file,
    "include-cycle": include_cycle,
}
# values are drawn three times as often: most other mutants stop at the compiler, a bad value
# is what gets through to the simulation
KINDS = list(TREE_MUTATIONS) + ["attribute", "attribute", "truncate", "two-at-once"]


def make_mutant(model, folder, work, index, rng):
    """Writes a mutant of `model` into `folder`; returns (path, kind, what, ctx)."""
    name = os.path.basename(model)
    mutant = os.path.join(folder, "hostile-%d-%s" % (index, name))
    with open(model, "rb") as f:
        raw = f.read()
    ctx = {"folder": folder, "work": work, "mutant": mutant, "removed": [], "extra": []}
    kind = rng.choice(KINDS)
    if kind == "truncate":
        cut = rng.randrange(len(raw)) if raw else 0
        with open(mutant, "wb") as f:
            f.write(raw[:cut])
        return mutant, kind, "truncated at byte %d of %d" % (cut, len(raw)), ctx
    try:
        root = ET.fromstring(raw)
    except ET.ParseError:
        return None
    compiler = root.find("compiler")
    if compiler is not None:
        ctx["meshdir"] = compiler.get("meshdir", compiler.get("assetdir", ""))
        ctx["texturedir"] = compiler.get("texturedir", compiler.get("assetdir", ""))
    kinds = rng.sample(list(TREE_MUTATIONS), 2) if kind == "two-at-once" else [kind]
    what = []
    for k in kinds:
        w = TREE_MUTATIONS[k](root, rng, ctx)
        if w is None:
            return None
        what.append(w)
    with open(mutant, "wb") as f:
        f.write(ET.tostring(root))
    return mutant, kind, "; ".join(what), ctx


def undo(ctx):
    for path, target in ctx["removed"]:
        os.symlink(target, path)
    for path in ctx["extra"] + [ctx["mutant"]]:
        if os.path.exists(path):
            os.remove(path)


def judge(name, proc, out_file, folder):
    """'' when the command ended cleanly, else what was wrong."""
    rc = proc.returncode
    err = proc.stderr.decode("utf-8", "replace")
    out = proc.stdout.decode("utf-8", "replace")
    if rc < 0:
        return "killed by signal %d" % -rc
    if rc not in CLEAN_EXITS:
        return "exit %d" % rc
    if re.search(r"(AddressSanitizer|UndefinedBehaviorSanitizer|runtime error:|LeakSanitizer)",
                 err):
        return "sanitizer report"
    if os.path.exists(os.path.join(folder, "MUJOCO_LOG.TXT")):
        return "MuJoCo's own error/warning handler ran (MUJOCO_LOG.TXT written)"
    if rc == 2 and not err.startswith("plumb"):
        return "exit 2 without a plumb message on stderr"
    if rc == 1 and (name in ("inspect", "snapshot") or not out.strip()):
        return "exit 1 without findings"
    if name == "snapshot":
        if rc == 0:
            try:
                with open(out_file) as f:
                    json.load(f)
            except (OSError, ValueError) as e:
                return "snapshot exit 0 but its file is not whole JSON (%s)" % e
        elif os.path.exists(out_file):
            return "snapshot exit %d left a file behind" % rc
    return ""


def run_mutant(plumb, mutant, timeout):
    folder = os.path.dirname(mutant)
    results = {}
    for name, args in COMMANDS:
        out_file = mutant + ".snap.json"
        argv = [plumb] + [a.format(model=mutant, out=out_file) for a in args]
        start = time.monotonic()
        try:
            proc = subprocess.run(argv, cwd=folder, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                                  timeout=timeout)
            problem = judge(name, proc, out_file, folder)
            results[name] = (proc.returncode, problem, proc.stderr.decode("utf-8", "replace"),
                             time.monotonic() - start)
        except subprocess.TimeoutExpired:
            results[name] = (None, "no answer within %g s (a hang)" % timeout, "", timeout)
        for leftover in (out_file, os.path.join(folder, "MUJOCO_LOG.TXT")):
            if os.path.exists(leftover):
                os.remove(leftover)
        for entry in os.listdir(folder):  # repro folders of diverged runs
            if entry.startswith("plumb-repro-"):
                shutil.rmtree(os.path.join(folder, entry), ignore_errors=True)
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--plumb", required=True)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--count", type=int, default=60)
    parser.add_argument("--timeout", type=float, default=240,
                        help="seconds a command may take before it counts as a hang")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--sample", type=int, default=0,
                        help="models drawn from each ROOT of more (0: all)")
    parser.add_argument("--json")
    parser.add_argument("--failures", default="hostile-failures")
    parser.add_argument("--robot-corpus", action="store_true",
                        help="add plumb's robot corpus (scripts/fetch-robots.sh) as a ROOT")
    parser.add_argument("roots", nargs="*")
    a = parser.parse_args()
    # a ROOT given that is not there is an error: a test must not pass on fewer models than
    # it names. The robot corpus is optional (make test CORPUS=off) unless
    # PLUMB_REQUIRE_CORPUS is set, as make test sets it.
    for root in a.roots:
        if not os.path.isdir(root):
            print("hostile_models.py: model folder %s is not there (MuJoCo's samples come "
                  "with Debian's libmujoco-samples: scripts/install-deps.sh)" % root,
                  file=sys.stderr)
            return 2
    if a.robot_corpus:  # where fetch-robots.sh puts it
        cache = os.environ.get("PLUMB_CACHE") or os.path.join(
            os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "plumb")
        corpus = os.path.join(cache, "robots")
        if os.path.isdir(corpus):
            a.roots.append(corpus)
        elif os.environ.get("PLUMB_REQUIRE_CORPUS"):
            print("hostile_models.py: the robot corpus is not in %s: run make corpus "
                  "(scripts/fetch-robots.sh)" % corpus, file=sys.stderr)
            return 2
        else:
            print("hostile_models.py: leaving out the robot corpus (not in %s; make corpus "
                  "fetches it)" % corpus, file=sys.stderr)
    rng = random.Random(a.seed)
    models = []
    for root in a.roots:
        models += find_models(root, a.sample, rng)
    if not models:
        print("hostile_models.py: no models found under %s" % ", ".join(a.roots),
              file=sys.stderr)
        return 2
    work = tempfile.mkdtemp(prefix="plumb-hostile-")
    folders = {}
    tally = collections.Counter()
    exits = collections.defaultdict(collections.Counter)
    defects = []
    per_kind = collections.Counter()
    start_count = 0
    record = []
    slowest = []  # (seconds, command, model, kind, mutation) of every command run

    def one(index, model):
        # each mutant has its own seed: a defect reproduces from --seed and its index
        r = random.Random("%d-%d" % (a.seed, index))
        for _ in range(20):  # a mutation that finds nothing to change is drawn again
            made = make_mutant(model, folders[model], work, index, r)
            if made:
                break
        else:
            return None
        mutant, kind, what, ctx = made
        try:
            results = run_mutant(a.plumb, mutant, a.timeout)
            if any(problem for _, problem, _, _ in results.values()):
                os.makedirs(a.failures, exist_ok=True)
                shutil.copy(mutant, os.path.join(a.failures, os.path.basename(mutant)))
            return model, kind, what, results
        finally:
            undo(ctx)

    # each model is mutated in a mirror of its folder; the mutants of one model run in
    # sequence (a mutation may take a file away from the mirror), different models in parallel
    groups = collections.defaultdict(list)
    for index in range(a.count):
        model = random.Random("m-%d-%d" % (a.seed, index)).choice(models)
        groups[model].append(index)
    for model in groups:
        folders[model] = mirror(model, work)

    def group(item):
        model, indices = item
        return [one(i, model) for i in indices]

    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        for answers in pool.map(group, groups.items()):
            for answer in answers:
                if answer is None:
                    continue
                model, kind, what, results = answer
                start_count += 1
                per_kind[kind] += 1
                for name, (rc, problem, err, seconds) in results.items():
                    exits[name][str(rc)] += 1
                    slowest.append((seconds, name, model, kind, what))
                    if problem:
                        defects.append({"model": model, "kind": kind, "mutation": what,
                                        "command": name, "exit": rc, "problem": problem,
                                        "stderr": err[-600:]})
                tally["clean" if all(not p for _, p, _, _ in results.values()) else "defect"] += 1
                record.append({"model": model, "kind": kind, "mutation": what,
                               "exits": {k: v[0] for k, v in results.items()},
                               "messages": {k: v[2].strip().splitlines()[0][:300]
                                            for k, v in results.items() if v[2].strip()}})
    shutil.rmtree(work, ignore_errors=True)
    summary = {"seed": a.seed, "models": len(models), "mutants": start_count,
               "kinds": dict(per_kind), "exits": {k: dict(v) for k, v in exits.items()},
               "defects": defects, "mutants": record}
    print("hostile models: %d mutants of %d models (seed %d); %d ended cleanly, %d with a defect"
          % (start_count, len(models), a.seed, tally["clean"], tally["defect"]))
    print("  kinds: " + ", ".join("%s %d" % kv for kv in sorted(per_kind.items())))
    for name, _ in COMMANDS:
        print("  %-9s exits: %s" % (name, ", ".join(
            "%s x%d" % kv for kv in sorted(exits[name].items()))))
    # slow is not a defect (a mutant may ask MuJoCo for more work, e.g. a solver tolerance
    # below 0 runs every iteration), but it is shown: a command near the limit says so here
    for seconds, name, model, kind, what in sorted(slowest, reverse=True)[:3]:
        print("  slow: %-8s %5.1f s on a mutant of %s (%s: %s)" % (name, seconds, model, kind,
                                                                  what))
    for d in defects:
        print("DEFECT: plumb %s on a mutant of %s (%s: %s): %s\n%s" % (
            d["command"], d["model"], d["kind"], d["mutation"], d["problem"],
            "\n".join("    " + line for line in d["stderr"].splitlines()[-6:])))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(summary, f, indent=1)
    return 1 if defects else 0


if __name__ == "__main__":
    sys.exit(main())
