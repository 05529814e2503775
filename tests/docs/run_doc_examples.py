#!/usr/bin/env python3
"""Runs every command example in the user documents, as a reader would type it.

Each line of a fenced code block in the given Markdown files that starts, at
its left edge, with `nlsoft-console` or `nlsoft-firmware-sim` is an example. Synopsis notation is
resolved the way a reader would first try it: an optional `[...]` group is
left out and `a|b|c` takes its first choice. Examples run in document order
in one scratch folder whose recording database and image cache are private
($XDG_DATA_HOME, $XDG_CACHE_HOME),
so `runs show 12` finds the runs recorded before it. Fixtures a reader would
have made first (a dozen recorded runs, a motion capture's file) are made
here and named in the output; a fenced block whose first line is
`# file: NAME` (a rig file, a reference table, a script, each of which
reads `#` as a comment) is written to NAME first, so the examples check the
very file the document shows (README's `tune.nls`, which app/CONSOLE.md
runs too: every file an example names is shown in one of the documents).
Such a block whose file also ships in rigs/examples/ (lab-arm.toml) must be
that file's text after its `# file:` line, or the run fails before its
first example; --shipped-only checks just that, in a second.

Under the sanitizers (--train-lbfgs K) a `train` example that sets no
--lbfgs runs with --lbfgs K: there it is checked for memory faults, not fit.

A fenced block right after a line `<!-- output of: WORDS -->` is what the
last example before it whose command starts with WORDS prints: each of its
lines must be a line of that example's output, so the figures a document
quotes (a model's hash, its fit, a tracking error) are the ones its own
commands give. Not checked under --train-lbfgs, whose cut-short training
gives other figures by design.

Figures in prose or a table are checked the same way through a line
`<!-- figures of: WORDS | F1 | F2 ... -->` right before the paragraph or
table that quotes them (its text: the lines up to the next blank line).
Each figure Fi, exactly as the command prints it ("3.00 %", "86092",
"0x1b2c3d4e"), must be in that text (so the marker and the prose cannot
drift apart) and in the output of the last example before the marker whose
command starts with WORDS, as a whole figure: no digit, '.' or ',' next to
it ("3.00 %" does not match "13.00 %"). A paragraph may carry several
markers, one per command, each on its own line before it. A figure that
depends on the machine's speed (a time) is never put under a marker: the
documents say such figures are measured, and by which command. Figures the
docs test cannot produce (a benchmark of minutes, a QEMU run of an image
under a profiler, a figure from before a change) name their command and
say that they are benchmark figures, not checked here.
`tests/docs/selftest/` shows a stale figure and a stale output failing.

A line ending in a backslash continues on the next. A synopsis, a line
with metavariables left to fill in (NAME, PORT), is listed as skipped.
Each example must exit 0, except that a board example (a /dev/tty* port,
`flash`) cannot run here and is listed as skipped with the reason, as are QEMU
examples and `firmware build` when the images were not built (--no-qemu: no
toolchain). Interactive examples (the TUI) run in tmux until the parameter
panel is drawn, then get `q`.

A `tune` example must also do what it shows: its best objective no higher
than its start's (the values in force, the presets), and no warning that
the reference barely moves in the window it scores.

The examples come in two parts, so that only the few that boot QEMU hold
ctest's one-QEMU-at-a-time lock (tests/docs/CMakeLists.txt):
  --part host  every example whose words do not contain `--qemu` (`firmware
               build` among them: it only compiles), and the fixtures above;
  --part qemu  the `--qemu` examples, in the folder the host part left, so
               they find its rig files, its recordings and the images its
               `firmware build` put in the image cache (`conformance --qemu
               lab-arm.toml` boots the one `firmware build ... --hil` made);
  --part all   (the default) both, in document order.
--work DIR is that folder: the host and all parts empty it first (only a
folder this script made, or an empty one) and leave it in place; the qemu
part refuses to start unless a host (or all) part went through its examples
there. Without --work the examples run in a temporary folder removed at the
end. A part prints the examples it runs or skips; the other part's are only
counted, in the last line. With --no-qemu there is no qemu part: the host
part lists the `--qemu` examples as skipped. Each part fails if it ran no
example.

  run_doc_examples.py --console C --firmware-sim S README.md ...    # all, by hand
  run_doc_examples.py ... --part host --work DIR README.md ...      # then:
  run_doc_examples.py ... --part qemu --work DIR README.md ...

Python rather than C++: it drives whole command lines and tmux, nothing else.
"""
import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

SUBCOMMANDS = {"runs", "conformance", "simulate", "dataset", "train", "model", "flash", "tune", "ports", "rig", "firmware",
               "ident"}


def named_files(path):
    """The fenced blocks that name their file (a rig file, a CSV, a script): {NAME: text}."""
    files, block, inside = {}, None, False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                if inside and block and block[0].startswith("# file: "):
                    files[block[0][len("# file: "):].strip()] = "".join(block)
                inside, block = not inside, []
                continue
            if inside:
                block.append(line)
    return files


REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHIPPED_EXAMPLES = os.path.join("rigs", "examples")


def shipped_copies_differ(docs):
    """A named block whose file also ships in rigs/examples/ must be that file's text (after its `# file:` line),
    so that the file a reader copies and the one the document shows cannot drift apart. Returns the complaints."""
    bad = []
    for doc in docs:
        for name, text in named_files(doc).items():
            shipped = os.path.join(REPO, SHIPPED_EXAMPLES, name)
            if not os.path.exists(shipped):
                continue
            with open(shipped, encoding="utf-8") as f:
                if f.read() != text.split("\n", 1)[1]:
                    bad.append(f"{os.path.basename(doc)}: the block `# file: {name}` is not {SHIPPED_EXAMPLES}/{name}: "
                               "change both alike")
    return bad


def examples(path):
    out, fenced, pending = [], False, None
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            if pending is not None:  # a line ending in a backslash goes on here
                where, text = pending
                text = text[:-1].rstrip() + " " + line.strip()
                pending = (where, text) if text.endswith("\\") else None
                if pending is None:
                    out.append((where, text))
                continue
            if line.startswith("```"):
                fenced = not fenced
                continue
            # At the block's left edge: an indented "nlsoft-console | ..." is a captured screen.
            if fenced and (line.startswith("nlsoft-console ") or line.startswith("nlsoft-firmware-sim ")):
                where, text = f"{os.path.basename(path)}:{n}", line.strip()
                if re.sub(r"\s+#\s.*$", "", text).endswith("\\"):
                    pending = (where, re.sub(r"\s+#\s.*$", "", text))
                else:
                    out.append((where, text))
    return out


def quoted_outputs(path):
    """The outputs a document quotes: [(line of the marker, WORDS, [lines])]."""
    out, words, where, block, fenced = [], None, 0, None, False
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            m = re.fullmatch(r"<!-- output of: (.+?) -->\s*", line)
            if m and not fenced:
                words, where = m.group(1).strip(), n
                continue
            if line.startswith("```"):
                fenced = not fenced
                if fenced and words is not None:
                    block = []
                elif not fenced and block is not None:
                    out.append((where, words, block))
                    words, block = None, None
                continue
            if block is not None:
                block.append(line.rstrip())
            elif not fenced and line.strip():
                words = None  # the marker must be right before its block
    return out


def quoted_figures(path):
    """The figures a document quotes in prose or a table:
    [(line of the marker, WORDS, [figures], text of the paragraph or table after it)]."""
    out, pending, fenced = [], [], False
    with open(path, encoding="utf-8") as f:
        lines = f.readlines()
    n = 0
    while n < len(lines):
        line = lines[n]
        if line.startswith("```"):
            fenced = not fenced
        m = None if fenced else re.fullmatch(r"<!-- figures of: (.+?) -->\s*", line)
        if m:
            parts = [p.strip() for p in m.group(1).split(" | ")]
            pending.append((n + 1, parts[0], [p for p in parts[1:] if p]))
            n += 1
            continue
        if pending:
            text = []
            while n < len(lines) and lines[n].strip():
                text.append(lines[n])
                n += 1
            out += [(where, words, figures, "".join(text)) for where, words, figures in pending]
            pending = []
            continue
        n += 1
    out += [(where, words, figures, "") for where, words, figures in pending]
    return out


def figure_in(figure, text):
    """`figure` in `text` as a whole figure: no digit, '.' or ',' right before or after it."""
    text = re.sub(r"\s+", " ", text)
    return re.search(r"(?<![0-9.,])" + re.escape(figure) + r"(?![0-9]|[.,][0-9])", text) is not None


def figures_verdict(quoted, ran):
    """Why the figures under a `figures of` marker are not what its example printed, or None."""
    where, words, figures, text = quoted
    if not figures:
        return "the marker names no figure (<!-- figures of: WORDS | F1 | F2 -->)"
    if not text:
        return "no paragraph or table right after the marker"
    untold = [f for f in figures if not figure_in(f, text)]
    if untold:
        return ("the marker names figures its paragraph does not quote (as printed, spacing aside): " +
                "; ".join(untold))
    before = [r for r in ran if r[0] < where and r[1].startswith(words)]
    if not before:
        return f"no example before it starts with '{words}'"
    missing = [f for f in figures if not figure_in(f, before[-1][2])]
    if missing:
        return ("the document quotes figures its example did not print: " + "; ".join(missing) +
                "\n  it printed:\n    " + "\n    ".join(before[-1][2].strip().splitlines()[-15:]))
    return None


def output_verdict(quoted, ran):
    """Why a quoted output is not what its example printed, or None.
    `ran`: [(line, shown command, output)] of the document's examples run here."""
    where, words, lines = quoted
    before = [r for r in ran if r[0] < where and r[1].startswith(words)]
    if not before:
        return f"no example before it starts with '{words}'"
    printed = {l.rstrip() for l in before[-1][2].splitlines()}
    missing = [l for l in lines if l.strip() and l not in printed]
    if missing:
        return ("the document quotes lines its example did not print:\n    " + "\n    ".join(missing) +
                "\n  it printed:\n    " + "\n    ".join(before[-1][2].strip().splitlines()[-15:]))
    return None


def placeholders(words):
    """Metavariables a reader must fill in (NAME, LO, PORT): the line is a synopsis."""
    return [p for w in words for p in re.split(r"[=.,:]+", w) if re.fullmatch(r"[A-Z][A-Z0-9_]*[A-Z][A-Z0-9_]*", p)]


def resolve(text):
    """The command line a reader would type first: comments off, optional groups out, first choices."""
    text = re.sub(r"\s+#\s.*$", "", text)
    while True:
        stripped = re.sub(r"\s*\[[^\[\]]*\]", "", text)
        if stripped == text:
            break
        text = stripped
    words = shlex.split(text)
    return [w.split("|")[0] if "|" in w and not w.startswith("-") else w for w in words]


def tune_verdict(out):
    """Why a tune example's output fails what it teaches, or None: it must
    score a window where the reference moves and end no worse than it began."""
    if "the reference barely moves" in out:
        return "tune warned that the reference barely moves in its window"
    m = re.search(r"^best: .* = ([-+0-9.eE]+) at evaluation (\d+) \(run \d+; nrmse [-+0-9.eE]+, start ([-+0-9.eE]+)\)",
                  out, re.M)
    if not m:
        return "tune printed no best with its start"
    best, at, start = float(m.group(1)), int(m.group(2)), float(m.group(3))
    print(f"  tune: start {start:.5g}, best {best:.5g} at evaluation {at}")
    if not best <= start:
        return f"tune's best {best:.5g} is above its start {start:.5g}"
    return None


def run(cmd, env, cwd, timeout):
    p = subprocess.run(cmd, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout)
    return p.returncode, p.stdout.decode(errors="replace")


_sessions = 0


def run_interactive(cmd, env, cwd, timeout):
    # A socket per example: a server being killed is never the next one's.
    global _sessions
    _sessions += 1
    sock = f"nlsoft-doc-{os.getpid()}-{_sessions}"
    tmux = ["tmux", "-L", sock]
    line = " ".join(shlex.quote(c) for c in cmd)
    envs = " ".join(f"{k}={shlex.quote(env[k])}" for k in ("NLSOFT_FIRMWARE_SIM", "XDG_DATA_HOME", "LANG") if k in env)
    started = subprocess.run(tmux + ["new-session", "-d", "-s", "doc", "-x", "120", "-y", "40", "-c", cwd,
                                     f"env {envs} {line}; echo EXIT=$?; sleep 30"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    if started.returncode != 0:
        return 1, "tmux did not start: " + started.stdout.decode(errors="replace")
    # kill-server leaves the socket file behind: removed after it.
    socket = subprocess.run(tmux + ["display-message", "-p", "#{socket_path}"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL).stdout.decode().strip()
    try:
        end, screen = time.time() + timeout, ""
        while time.time() < end:
            screen = subprocess.run(tmux + ["capture-pane", "-p", "-t", "doc"], stdout=subprocess.PIPE).stdout.decode()
            if "Parameters (" in screen or "EXIT=" in screen:
                break
            time.sleep(0.2)
        if "Parameters (" not in screen:
            return 1, screen
        subprocess.run(tmux + ["send-keys", "-t", "doc", "q"])
        while time.time() < end:
            screen = subprocess.run(tmux + ["capture-pane", "-p", "-t", "doc"], stdout=subprocess.PIPE).stdout.decode()
            m = re.search(r"EXIT=(\d+)", screen)
            if m:
                return int(m.group(1)), screen
            time.sleep(0.2)
        return 1, screen + "\n(did not exit after q)"
    finally:
        subprocess.run(tmux + ["kill-server"], stderr=subprocess.DEVNULL)
        if socket.endswith(sock):
            try:
                os.remove(socket)
            except OSError:
                pass


# The folder's marks: this script made it (so emptying it destroys nothing
# else), and the host part went through every example in it.
OWNED, HOST_DONE = ".nlsoft-doc-examples", ".nlsoft-doc-examples-host-done"


def boots_qemu(cmd):
    return any(w == "--qemu" or w.startswith("--qemu=") for w in cmd)


def fresh_folder(work):
    """Empties `work` (made if missing), refusing a folder this script did not make."""
    if os.path.isdir(work) and os.listdir(work) and not os.path.exists(os.path.join(work, OWNED)):
        sys.exit(f"{work} holds files this script did not put there: not emptying it (give --work an empty "
                 "or new folder)")
    if os.path.isdir(work):
        shutil.rmtree(work)
    os.makedirs(work)
    with open(os.path.join(work, OWNED), "w") as f:
        f.write("run_doc_examples.py's scratch folder: emptied at the start of every host or all part\n")


def make_fixtures(a, work, env):
    """What a reader would have made first; False if one could not be made."""
    # Runs 1..13 to show, export and compare, a capture. (The scripts the
    # examples run are the documents' own `# file:` blocks, below.)
    with open(os.path.join(work, "runs.nls"), "w") as f:
        f.write("".join(f"run 200ms label=fixture{i}\n" for i in range(1, 14)))
    code, out = run([a.console, "--sim", "msd", "--sim-fast", "--script", "runs.nls"], env, work, 120)
    print(f"fixture: 13 runs recorded ({'ok' if code == 0 else 'FAILED'})")
    if code != 0:
        print(out)
        return False

    # A motion capture's file (CONSOLE.md, `--y-from`): the outputs of the
    # identification run the example records, on a clock 12.5 s ahead,
    # as a capture program would have written them.
    fixture_db, export = os.path.join(work, "mocap-fixture.db"), os.path.join(work, "mocap-fixture.csv")
    code, out = run([a.console, "ident", "--sim", "hasel", "--signal", "prbs", "--duration", "60s", "--sim-fast",
                     "--db", fixture_db], env, work, 120)
    if code == 0:
        code, out = run([a.console, "runs", "export", "1", "--csv", export, "--db", fixture_db], env, work, 60)
    print(f"fixture: mocap.csv ({'ok' if code == 0 else 'FAILED'})")
    if code != 0:
        print(out)
        return False
    with open(export, encoding="utf-8") as f, open(os.path.join(work, "mocap.csv"), "w") as capture:
        head = f.readline().strip().split(",")
        step, ys = head.index("step"), [i for i, h in enumerate(head) if h.startswith("y_true")]
        capture.write("time," + ",".join(f"y{j}" for j in range(len(ys))) + "\n")
        for line in f:
            cells = line.strip().split(",")
            capture.write(f"{int(cells[step]) / 130.0 + 12.5:.6f}," + ",".join(cells[i] for i in ys) + "\n")

    drift = shipped_copies_differ(a.docs)
    for d in drift:
        print(f"FAIL: {d}")
    if drift:
        return False
    for doc in a.docs:
        for name, text in named_files(doc).items():
            with open(os.path.join(work, name), "w") as f:
                f.write(text)
            print(f"fixture: {name} from {os.path.basename(doc)}")
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--console")
    ap.add_argument("--firmware-sim")
    ap.add_argument("--shipped-only", action="store_true",
                    help="only check that the documents' named blocks are the files shipped in rigs/examples/")
    ap.add_argument("--no-qemu", action="store_true", help="the Cortex-M images were not built: skip QEMU examples "
                    "and `firmware build`")
    ap.add_argument("--part", choices=("all", "host", "qemu"), default="all",
                    help="host: the examples that do not boot QEMU (and the fixtures); qemu: those that do, "
                         "continuing in the host part's --work folder; all (default): both in document order")
    ap.add_argument("--work", help="the scratch folder, emptied first by the host and all parts and kept; "
                    "default: a temporary folder removed at the end")
    ap.add_argument("--train-lbfgs", type=int,
                    help="a `train` example that sets no --lbfgs gets --lbfgs K: the sanitizer builds, where "
                         "training for simulation runs ten times slower and is checked for memory faults, not fit")
    ap.add_argument("docs", nargs="+")
    a = ap.parse_args()
    if a.shipped_only:
        drift = shipped_copies_differ(a.docs)
        for d in drift:
            print(f"FAIL: {d}")
        checked = [n for doc in a.docs for n in named_files(doc)
                   if os.path.exists(os.path.join(REPO, SHIPPED_EXAMPLES, n))]
        print(f"{len(checked)} shipped example file(s) checked against the documents: {', '.join(checked) or 'none'}")
        return 1 if drift or not checked else 0
    if not a.console or not a.firmware_sim:
        ap.error("--console and --firmware-sim are required to run the examples")
    if a.part == "qemu" and a.no_qemu:
        ap.error("--part qemu runs only QEMU examples, which --no-qemu skips: nothing to run")
    if a.part == "qemu" and not a.work:
        ap.error("--part qemu continues in the host part's folder: give it the same --work")
    a.console, a.firmware_sim = os.path.abspath(a.console), os.path.abspath(a.firmware_sim)

    if a.work:
        work = os.path.abspath(a.work)
        if a.part == "qemu":
            if not os.path.exists(os.path.join(work, HOST_DONE)):
                print(f"no host part finished in {work}: run docs.EveryCommandExampleRuns first (or this script "
                      f"with --part host --work {work}); the QEMU examples continue in its folder, with its rig "
                      "files, recordings and images")
                return 1
            with open(os.path.join(work, HOST_DONE)) as f:
                print(f"continuing in {work} after the host part ({f.read().strip()})")
        else:
            fresh_folder(work)
    else:
        work = tempfile.mkdtemp(prefix="nlsoft-doc-examples-")
    # The images `firmware build` makes go to the scratch folder's cache, not the user's.
    env = dict(os.environ, XDG_DATA_HOME=os.path.join(work, "data"), XDG_CACHE_HOME=os.path.join(work, "cache"),
               NLSOFT_FIRMWARE_SIM=a.firmware_sim, LANG="C.UTF-8")
    binaries = {"nlsoft-console": a.console, "nlsoft-firmware-sim": a.firmware_sim}
    failed = ran = skipped = elsewhere = 0
    try:
        if a.part != "qemu" and not make_fixtures(a, work, env):
            return 1
        for doc in a.docs:
            ran_here = []  # (line, shown command, output) of this document's examples run in this part
            for where, text in examples(doc):
                cmd = resolve(text)
                cmd[0] = binaries[cmd[0]]
                shown = " ".join(resolve(text))
                # Without the images there is no QEMU part: the host part lists them as skipped.
                if a.part != "all" and not a.no_qemu and (a.part == "qemu") != boots_qemu(cmd):
                    elsewhere += 1
                    continue
                if any(w.startswith("/dev/tty") for w in cmd) or (len(cmd) > 1 and cmd[1] == "flash"):
                    print(f"SKIP {where}: {shown}  (needs a board on a serial port)")
                    skipped += 1
                    continue
                if placeholders(cmd[1:]):
                    print(f"SKIP {where}: {shown}  (a synopsis: {', '.join(placeholders(cmd[1:]))} to fill in)")
                    skipped += 1
                    continue
                if a.no_qemu and (boots_qemu(cmd) or (len(cmd) > 1 and cmd[1] == "firmware")):
                    print(f"SKIP {where}: {shown}  (the Cortex-M images were not built)")
                    skipped += 1
                    continue
                if a.train_lbfgs is not None and len(cmd) > 1 and cmd[1] == "train" and "--lbfgs" not in cmd:
                    cmd += ["--lbfgs", str(a.train_lbfgs)]
                    shown += f"  (--lbfgs {a.train_lbfgs} added: --train-lbfgs)"
                started = time.time()
                if cmd[0] == a.firmware_sim:
                    p = subprocess.Popen(cmd, env=env, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
                    first = p.stdout.readline().decode().strip()
                    p.terminate()
                    p.wait(timeout=10)
                    code, out = (0, first) if first.startswith("/dev/pts/") else (1, first)
                elif len(cmd) > 1 and cmd[1] not in SUBCOMMANDS and "--script" not in cmd:
                    code, out = run_interactive(cmd, env, work, 60)
                else:
                    code, out = run(cmd, env, work, 600)
                    if code == 0 and len(cmd) > 1 and cmd[1] == "tune":
                        why = tune_verdict(out)
                        if why:
                            code, out = 1, out + "\n" + why
                ran += 1
                ran_here.append((int(where.rsplit(":", 1)[1]), shown, out))
                verdict = "PASS" if code == 0 else "FAIL"
                print(f"{verdict} {where}: {shown}  ({time.time() - started:.1f} s)")
                if code != 0:
                    failed += 1
                    print("  exit", code, "\n  " + "\n  ".join(out.strip().splitlines()[-15:]))
            for quoted in quoted_outputs(doc):
                # Its example runs in the other part (a QEMU one): checked there.
                if not any(r[1].startswith(quoted[1]) for r in ran_here) or a.train_lbfgs is not None:
                    continue
                why = output_verdict(quoted, ran_here)
                print(f"{'FAIL' if why else 'PASS'} {os.path.basename(doc)}:{quoted[0]}: the output of '{quoted[1]}' "
                      "as quoted")
                if why:
                    failed += 1
                    print("  " + why)
            for quoted in quoted_figures(doc):
                if not any(r[1].startswith(quoted[1]) for r in ran_here) or a.train_lbfgs is not None:
                    if a.part == "all" and a.train_lbfgs is None:  # no part runs its example: a stale marker
                        print(f"FAIL {os.path.basename(doc)}:{quoted[0]}: no example starts with '{quoted[1]}'")
                        failed += 1
                    continue
                why = figures_verdict(quoted, ran_here)
                print(f"{'FAIL' if why else 'PASS'} {os.path.basename(doc)}:{quoted[0]}: the figures of "
                      f"'{quoted[1]}' as quoted ({len(quoted[2])})")
                if why:
                    failed += 1
                    print("  " + why)
        if a.part != "qemu":
            with open(os.path.join(work, HOST_DONE), "w") as f:
                f.write(f"{ran} examples run, {failed} failed\n")
    finally:
        if not a.work:
            shutil.rmtree(work, ignore_errors=True)
    print(f"{ran} examples run, {failed} failed, {skipped} skipped"
          + (f", {elsewhere} left to the other part" if elsewhere else ""))
    return 1 if failed or ran == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
