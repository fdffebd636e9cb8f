#!/usr/bin/env python3
"""Every code block of the docs, run: so that a page cannot drift from the code it describes.

    doc_blocks.py check --pldamp PATH --build DIR --source DIR [--cpp-program PATH] PAGE...
    doc_blocks.py extract-cpp OUT.cpp PAGE...

A block is a fenced block whose info string names its kind, and optionally attributes in braces
(```sh {ran-by=install_consumer_test}):

- console: `$ command` lines (a trailing `\\` continues one), each followed by the output it must
  print. Commands are started with an argument vector (no shell), in a folder that links to the
  repository's files and keeps what they write; build/harness/pldamp is the build's. Output is compared as doctest compares it
  (ELLIPSIS, NORMALIZE_WHITESPACE): `...` stands for any text, a `  # note` ends an expected line
  unread, and a last line `(exit status N)` gives the status (else 0, or 2 after "error:").
- python: with `>>>`, a doctest (the blocks of one page share their names); without, a script.
- cpp: compiled by CMake (target doc_blocks_cpp, from `extract-cpp`), each page's blocks in order
  in one function, as a notebook runs; a `text {output}` block after one is what it must print.
- toml: a scene, run by `pldamp run`; {fragment} adds the grid it leaves out.
- bash {slurm=array|step|merge}: a Slurm batch script, run with Slurm's variables set and pldamp
  and srun stood in for: an array's every task (as written and 0-based, in the array and rerun
  alone) runs its own --shard of the set; a step starts pldamp by srun --mpi=pmix; a merge merges.
- sh: each line a command; build/harness/pldamp and python3 lines are run (status 0), and a block
  holding other commands (an install, a build, a cluster job) names the ctest that runs them
  ({ran-by=NAME}, checked to exist; `ci` is the CI job itself) or why none can ({norun=why}).
- cmake: each line is in examples/cmake-consumer/CMakeLists.txt, which install_consumer_test builds.
- yaml: parsed (a CI job's configuration).
- text: prose-like (a synopsis, a layout, a grammar): not run.

An indented code block that holds a command or code is an error: it would escape the test.
"""
import doctest
import os
import re
import shlex
import subprocess
import sys
import tempfile

KINDS = {"console", "python", "cpp", "toml", "sh", "bash", "cmake", "yaml", "text"}
FENCE = re.compile(r"^(\s*)```(\S*)\s*(\{[^}]*\})?\s*$")
CODE_LIKE = re.compile(r"^ {4,}(\$ |>>> |#include|build/|pldamp |python3 |cmake |scripts/|mpirun )")
SEPARATOR = "=== pldamp doc block "


class Block:
    def __init__(self, path, line, kind, attributes, text):
        self.path, self.line, self.kind, self.attributes, self.text = path, line, kind, attributes, text

    def where(self):
        return f"{self.path}:{self.line}"


def attributes_of(braces):
    out = {}
    for word in shlex.split((braces or "{}")[1:-1]):
        key, _, value = word.partition("=")
        out[key] = value
    return out


def blocks_of(path):
    """The fenced blocks of a page, and the errors of its unfenced ones."""
    lines = open(path, encoding="utf-8").read().split("\n")
    blocks, errors, i = [], [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if m:
            indent, kind, braces = len(m.group(1)), m.group(2), m.group(3)
            j = i + 1
            while j < len(lines) and not lines[j].strip().startswith("```"):
                j += 1
            if j == len(lines):
                errors.append(f"{path}:{i + 1}: a fence that is never closed")
                break
            text = "\n".join(l[indent:] if l[:indent].strip() == "" else l for l in lines[i + 1:j])
            if kind not in KINDS:
                errors.append(f"{path}:{i + 1}: a block of kind '{kind}' (give one of "
                              f"{', '.join(sorted(KINDS))})")
            else:
                blocks.append(Block(path, i + 1, kind, attributes_of(braces), text + "\n"))
            i = j + 1
            continue
        if CODE_LIKE.match(lines[i]) and (i == 0 or lines[i - 1].strip() == ""):
            errors.append(f"{path}:{i + 1}: an indented code block; fence it with its kind so that "
                          f"a test runs it: {lines[i].strip()[:60]}")
        i += 1
    return blocks, errors


def matches(expected, actual):
    """doctest's ELLIPSIS and NORMALIZE_WHITESPACE, with `  # note` cut from expected lines."""
    lines = [re.sub(r"\s+#\s.*$", "", l) for l in expected.split("\n")]
    want = " ".join(" ".join(lines).split())
    got = " ".join(actual.split())
    pattern = ".*?".join(re.escape(part) for part in want.split("..."))
    return re.fullmatch(pattern, got, re.DOTALL) is not None


def run(argv, context, timeout=600):
    env = dict(os.environ)
    while argv and re.fullmatch(r"[A-Z_][A-Z0-9_]*=.*", argv[0]):
        name, _, value = argv.pop(0).partition("=")
        env[name] = value.replace("build/python", context["python_path"])
    env.setdefault("PYTHONPATH", context["python_path"])
    if argv and argv[0] == "build/harness/pldamp":
        argv[0] = context["pldamp"]
    elif argv and argv[0] == "python3":
        argv[0] = sys.executable
    result = subprocess.run(argv, cwd=context["sandbox"], env=env, capture_output=True, text=True,
                            timeout=timeout)
    return result.returncode, result.stdout + result.stderr


def logical_lines(text):
    out, pending = [], ""
    for line in text.split("\n"):
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        out.append(pending + line)
        pending = ""
    return out


def check_console(block, context):
    errors, commands, current = [], [], None
    for line in logical_lines(block.text):
        if line.startswith("$ "):
            current = [line[2:], []]
            commands.append(current)
        elif current is None:
            if line.strip():
                errors.append(f"{block.where()}: output before any `$ ` command")
        else:
            current[1].append(line)
    for command, output in commands:
        expected = "\n".join(output).strip()
        status = 2 if expected.startswith("error:") else 0
        m = re.search(r"\(exit status (\d+)\)\s*$", expected)
        if m:
            status = int(m.group(1))
            expected = expected[:m.start()]
        code, printed = run(shlex.split(command, comments=True), context)
        if code != status:
            errors.append(f"{block.where()}: `{command}` exited {code}, the page says {status}:\n"
                          f"{printed[:2000]}")
        elif expected and not matches(expected, printed):
            errors.append(f"{block.where()}: `{command}` printed\n{printed[:3000]}\n"
                          f"which is not what the page shows:\n{expected}")
    return errors


def check_python(block, context, globs):
    if ">>>" not in block.text:
        code, printed = run(["python3", "-c", block.text], context)
        return [] if code == 0 else [f"{block.where()}: the script exited {code}:\n{printed}"]
    test = doctest.DocTestParser().get_doctest(block.text, globs, block.where(), block.path,
                                               block.line)
    report = []
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    here = os.getcwd()
    os.chdir(context["sandbox"])  # where the commands run: data/scenes/quick.toml is there
    try:
        runner.run(test, out=report.append, clear_globs=False)
    finally:
        os.chdir(here)
    globs.update(test.globs)  # a page's blocks share their names, as a notebook's cells do
    return [f"{block.where()}: doctest failed:\n{''.join(report)}"] if report else []


def check_toml(block, context):
    with tempfile.TemporaryDirectory() as work:
        text = block.text
        if "fragment" in block.attributes:
            solver = "" if "[[solver]]" in text else '[[solver]]\nname = "taylor"\n'
            text = ('name = "doc fragment"\nwant = ["e"]\n[grid]\np = [1.5]\ne = [0.5]\n'
                    'v0 = [1.0]\n' + solver + text)
        # A scene two folders below a folder holding the repository's adapters, as data/scenes is.
        folder = os.path.join(work, "data", "scenes")
        os.makedirs(folder)
        os.symlink(os.path.abspath(os.path.join(context["source"], "adapters")),
                   os.path.join(work, "adapters"))
        scene = os.path.join(folder, "scene.toml")
        open(scene, "w").write(text)
        code, printed = run(["build/harness/pldamp", "run", scene, "--out",
                             os.path.join(work, "out")], context)
        return [] if code == 0 else [f"{block.where()}: the scene did not run ({code}):\n{printed}"]


def check_sh(block, context):
    if "norun" in block.attributes:
        return [] if block.attributes["norun"] else [f"{block.where()}: norun needs a reason"]
    ran_by = block.attributes.get("ran-by")
    if ran_by:
        if ran_by == "ci" or ran_by in context["ctests"] or ran_by in context["ci_scripts"]:
            return []
        return [f"{block.where()}: ran-by={ran_by}, which is neither a ctest of this build nor a "
                f"script scripts/run.sh runs"]
    errors = []
    for line in logical_lines(block.text):
        argv = shlex.split(line, comments=True)
        if not argv:
            continue
        program = next((a for a in argv if not re.fullmatch(r"[A-Z_][A-Z0-9_]*=.*", a)), "")
        if program not in ("build/harness/pldamp", "python3"):
            errors.append(f"{block.where()}: `{line.strip()}` is not run here: name the ctest "
                          f"that runs it ({{ran-by=NAME}}) or why none can ({{norun=why}})")
            continue
        code, printed = run(argv, context)
        if code != 0:
            errors.append(f"{block.where()}: `{line.strip()}` exited {code}:\n{printed[:2000]}")
    return errors


STUB = """#!/bin/sh
# Stands in for a program a Slurm script starts: writes its arguments, one per line, then a blank.
printf '%s\\n' "$(basename "$0")" "$@" "" >>"$STUB_LOG"
"""


def run_slurm_script(text, env_extra):
    """Runs a Slurm batch script as Slurm would start it, with build/harness/pldamp and srun
    replaced by stubs that record their arguments: the commands it would run, as argv lists."""
    with tempfile.TemporaryDirectory() as work:
        for stub in ("build/harness/pldamp", "bin/srun"):
            os.makedirs(os.path.join(work, os.path.dirname(stub)), exist_ok=True)
            with open(os.path.join(work, stub), "w") as out:
                out.write(STUB)
            os.chmod(os.path.join(work, stub), 0o755)
        script = os.path.join(work, "job.sh")
        open(script, "w").write(text)
        log = os.path.join(work, "log")
        env = {"PATH": os.path.join(work, "bin") + ":/usr/bin:/bin", "STUB_LOG": log,
               "SLURM_JOB_ID": "4242", "SLURM_CPUS_PER_TASK": "8", **env_extra}
        result = subprocess.run(["bash", script], cwd=work, env=env, capture_output=True,
                                text=True, timeout=60)
        if result.returncode != 0:
            raise AssertionError(f"exited {result.returncode}: {result.stderr}")
        calls = open(log).read().split("\n\n") if os.path.exists(log) else []
        return [call.split("\n") for call in calls if call.strip()]


def shard_of(call):
    return call[call.index("--shard") + 1], call[call.index("--out") + 1]


def check_slurm_array(block, text):
    """Every task of the array runs its own shard of the whole set, and a task rerun alone
    (sbatch --array=K) the same one: for the array as written, and made 0-based."""
    errors = []
    m = re.search(r"^#SBATCH --array=(\d+)-(\d+)\s*$", text, re.M)
    if not m:
        return [f"{block.where()}: an array script without '#SBATCH --array=A-B'"]
    low, high = int(m.group(1)), int(m.group(2))
    count = high - low + 1
    zero_based = text.replace(m.group(0), f"#SBATCH --array=0-{count - 1}")
    zero_based = re.sub(r"^first=\d+$", "first=0", zero_based, flags=re.M)
    for variant, script, first in (("as written", text, low), ("0-based", zero_based, 0)):
        shards, outs = {}, set()
        for task in range(first, first + count):
            whole = {"SLURM_ARRAY_TASK_ID": str(task), "SLURM_ARRAY_TASK_COUNT": str(count),
                     "SLURM_ARRAY_TASK_MIN": str(first),
                     "SLURM_ARRAY_TASK_MAX": str(first + count - 1)}
            alone = {"SLURM_ARRAY_TASK_ID": str(task), "SLURM_ARRAY_TASK_COUNT": "1",
                     "SLURM_ARRAY_TASK_MIN": str(task), "SLURM_ARRAY_TASK_MAX": str(task)}
            try:
                [call] = run_slurm_script(script, whole)
                [rerun] = run_slurm_script(script, alone)
            except (AssertionError, ValueError) as error:
                return [f"{block.where()}: {variant}, task {task}: {error}"]
            shards[task], out = shard_of(call)
            outs.add(out)
            if shard_of(rerun) != shard_of(call):
                errors.append(f"{block.where()}: {variant}, task {task} rerun alone runs "
                              f"{shard_of(rerun)}, in the array {shard_of(call)}")
        want = {f"{k}/{count}" for k in range(1, count + 1)}
        if set(shards.values()) != want or len(outs) != count:
            errors.append(f"{block.where()}: {variant}: the tasks run shards "
                          f"{sorted(set(shards.values()))[:5]}... into {len(outs)} folders, not "
                          f"each of 1/{count} ... {count}/{count} once")
    return errors


def check_slurm(block, context):
    kind = block.attributes.get("slurm")
    if kind == "array":
        return check_slurm_array(block, block.text)
    try:
        calls = run_slurm_script(block.text, {"SLURM_NTASKS": "16"})
    except AssertionError as error:
        return [f"{block.where()}: {error}"]
    if kind == "step":
        ok = len(calls) == 1 and calls[0][0] == "srun" and "--mpi=pmix" in calls[0] and \
            "build/harness/pldamp" in calls[0] and "run" in calls[0]
        return [] if ok else [f"{block.where()}: the step must start pldamp run by srun "
                              f"--mpi=pmix (it ran {calls})"]
    if kind == "merge":
        ok = len(calls) == 1 and calls[0][:2] == ["pldamp", "merge"]
        return [] if ok else [f"{block.where()}: the script must run pldamp merge (it ran {calls})"]
    return [f"{block.where()}: slurm={kind}, expected array, step or merge"]


def check_cmake(block, context):
    consumer = open(os.path.join(context["source"], "examples", "cmake-consumer",
                                 "CMakeLists.txt")).read()
    have = {" ".join(re.sub(r"#.*", "", l).split()) for l in consumer.split("\n")}
    return [f"{block.where()}: `{line.strip()}` is not in examples/cmake-consumer/CMakeLists.txt"
            for line in block.text.split("\n")
            if re.sub(r"#.*", "", line).strip()
            and " ".join(re.sub(r"#.*", "", line).split()) not in have]


def check_yaml(block, context):
    try:
        import yaml
    except ImportError:
        return []
    try:
        yaml.safe_load(block.text)
        return []
    except yaml.YAMLError as error:
        return [f"{block.where()}: not YAML: {error}"]


def cpp_key(block):
    return f"{os.path.abspath(block.path)}:{block.line}"


def cpp_blocks(paths):
    """Per page, its cpp blocks, each with the output block after it (or None)."""
    pages = []
    for path in paths:
        blocks, _ = blocks_of(path)
        pairs = []
        for i, block in enumerate(blocks):
            if block.kind == "cpp":
                after = blocks[i + 1] if i + 1 < len(blocks) else None
                output = after if after and after.kind == "text" and "output" in after.attributes \
                    else None
                pairs.append((block, output))
        if pairs:
            pages.append((path, pairs))
    return pages


def extract_cpp(out, paths):
    includes, bodies = [], []
    for n, (path, pairs) in enumerate(cpp_blocks(paths)):
        body = []
        for block, _ in pairs:
            body.append(f'  std::cout << "{SEPARATOR}{cpp_key(block)}" << std::endl;')
            body.append(f"#line {block.line + 1} \"{os.path.abspath(block.path)}\"")
            for line in block.text.split("\n"):
                if line.startswith("#include"):
                    includes.append(line)
                    body.append("")
                else:
                    body.append("  " + line)
            body.append("  std::cout << std::flush;")
        bodies.append((n, path, body))
    text = ["// Generated by tests/docs/doc_blocks.py from the docs' cpp blocks: do not edit.",
            "#include <iostream>"]
    text += sorted(set(includes))
    for n, path, body in bodies:
        text.append(f"// {path}")
        text.append(f"static void page_{n}() {{")
        text += body
        text.append("}")
    text.append("int main() {")
    text += [f"  page_{n}();" for n, _, _ in bodies]
    text.append("}")
    new = "\n".join(text) + "\n"
    if not os.path.exists(out) or open(out).read() != new:  # unchanged: no rebuild
        open(out, "w").write(new)


def check_cpp(pages, context):
    if not pages:
        return []
    program = context.get("cpp_program")
    if not program:
        return [f"{pages[0][1][0][0].where()}: cpp blocks, and no --cpp-program built from them"]
    result = subprocess.run([program], capture_output=True, text=True, timeout=600)
    if result.returncode != 0:
        return [f"{program} exited {result.returncode}:\n{result.stdout}{result.stderr}"]
    printed = {}
    for chunk in result.stdout.split(SEPARATOR)[1:]:
        where, _, text = chunk.partition("\n")
        printed[where] = text
    errors = []
    for _, pairs in pages:
        for block, output in pairs:
            got = printed.get(cpp_key(block))
            if got is None:
                errors.append(f"{block.where()}: not in {program}: rebuild doc_blocks_cpp")
            elif output is not None and not matches(output.text.strip(), got):
                errors.append(f"{block.where()}: printed\n{got}\nnot what the page shows:\n"
                              f"{output.text}")
            elif output is None and got.strip():
                errors.append(f"{block.where()}: printed\n{got}\nwhich the page does not show "
                              f"(a text {{output}} block after it)")
    return errors


def check_citations(source):
    """Every citation of a page's section (docs/, then the page's name, then the section quoted;
    or README and the section) the sources and docs write names text that page holds: a section moved or renamed is found here, not by a reader."""
    cite = re.compile(r'(?<!")(docs/[\w.-]+\.md|README)\s*,?\s*"([^"\n]{3,80})"')
    normal = lambda text: " ".join(text.replace("`", "").split()).lower()
    pages, errors, cited = {}, [], 0
    for folder in ("core", "analytic", "solvers", "harness", "python", "tests", "bench", "data",
                   "adapters", "scripts", "docs", "examples", ""):
        top = os.path.join(source, folder)
        walk = os.walk(top) if folder else [(top, [], os.listdir(top))]
        for root, _, names in walk:
            for name in names:
                if not name.endswith((".cpp", ".hpp", ".py", ".sh", ".md", ".toml", ".txt")):
                    continue
                path = os.path.join(root, name)
                if "/fuzz/corpus" in path or path.endswith("doc_blocks.py") or \
                        not os.path.isfile(path):
                    continue
                text = open(path, encoding="utf-8", errors="replace").read()
                for m in cite.finditer(" ".join(text.replace("//", " ").replace("#", " ").split())):
                    page = "README.md" if m.group(1) == "README" else m.group(1)
                    if page not in pages:
                        target = os.path.join(source, page)
                        pages[page] = normal(open(target).read()) if os.path.isfile(target) else ""
                    cited += 1
                    if normal(m.group(2)) not in pages[page]:
                        errors.append(f"{os.path.relpath(path, source)} cites {page} "
                                      f"\"{m.group(2)}\", which that page does not hold")
    if cited < 20:
        errors.append(f"only {cited} citations of a page's section found: is the search broken?")
    return errors


def check_links(paths):
    """Every relative link of a page leads to a file (pages moved between folders broke some)."""
    errors = []
    for path in paths:
        text = open(path, encoding="utf-8").read()
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            file = target.split("#")[0]
            if file and not re.match(r"[a-z]+:", file) and \
                    not os.path.exists(os.path.join(os.path.dirname(path), file)):
                errors.append(f"{path}: a link to {target}, which is not there")
    return errors


def main(argv):
    if argv[:1] == ["extract-cpp"]:
        extract_cpp(argv[1], argv[2:])
        return 0
    assert argv[:1] == ["check"], __doc__
    context, files, i = {}, [], 1
    while i < len(argv):
        if argv[i].startswith("--"):
            context[argv[i][2:].replace("-", "_")] = argv[i + 1]
            i += 2
        else:
            files.append(argv[i])
            i += 1
    context["python_path"] = context.get("python_path", os.path.join(context["build"], "python"))
    for key in ("pldamp", "build", "source", "python_path", "cpp_program"):
        if key in context:
            context[key] = os.path.abspath(context[key])
    sys.path.insert(0, context["python_path"])  # the doctests import pldamp
    # Commands run in a folder of their own that sees the repository's files (a link to each) but
    # keeps what they write (a report folder) out of the source tree.
    sandbox = tempfile.TemporaryDirectory()
    context["sandbox"] = sandbox.name
    for name in os.listdir(context["source"]):
        if not name.startswith(".") and name != "build":
            os.symlink(os.path.abspath(os.path.join(context["source"], name)),
                       os.path.join(sandbox.name, name))
    listed = subprocess.run(["ctest", "-N"], cwd=context["build"], capture_output=True, text=True)
    context["ctests"] = set(re.findall(r"Test\s+#\d+: (\S+)", listed.stdout))
    ci = open(os.path.join(context["source"], "scripts", "run.sh")).read()
    context["ci_scripts"] = {path for path in re.findall(r"(?:scripts|tests)/[\w/.-]+\.sh", ci)
                             if os.path.isfile(os.path.join(context["source"], path))}
    errors, counts = [], {}
    for path in files:
        blocks, unfenced = blocks_of(path)
        errors += unfenced
        globs = {}
        for block in blocks:
            counts[block.kind] = counts.get(block.kind, 0) + 1
            check = {"console": check_console, "toml": check_toml, "sh": check_sh,
                     "bash": check_sh, "cmake": check_cmake, "yaml": check_yaml}.get(block.kind)
            if block.kind == "python":
                errors += check_python(block, context, globs)
            elif block.kind == "bash" and "slurm" in block.attributes:
                errors += check_slurm(block, context)
            elif check:
                errors += check(block, context)
    errors += check_cpp(cpp_blocks(files), context)
    errors += check_citations(context["source"])
    errors += check_links(files)
    for error in errors:
        print(error, end="\n\n")
    print(f"{sum(counts.values())} blocks in {len(files)} pages "
          f"({', '.join(f'{n} {k}' for k, n in sorted(counts.items()))}): "
          f"{len(errors)} failed")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
