#!/usr/bin/env python3
"""run_doc_examples.py's own test, in seconds: against a fake console that
prints fixed figures (fake-console), a document whose quotes are what it
printed passes, and each stale one fails naming the stale figure:
  stale-figure.md    a prose figure the command no longer prints (95432 B)
  untold-figure.md   a marker's figure the paragraph does not quote (it says 3.49 %)
  partial-figure.md  a figure found only inside another ("00 %" in "3.00 %")
  stale-output.md    a quoted output block with a line the command did not print
"""
import os
import subprocess
import sys

here = os.path.dirname(os.path.abspath(__file__))
script = os.path.join(os.path.dirname(here), "run_doc_examples.py")
fake = os.path.join(here, "fake-console")  # the firmware simulator is never started: /bin/true


def run(doc):
    p = subprocess.run([sys.executable, script, "--console", fake, "--firmware-sim", "/bin/true", "--no-qemu",
                        os.path.join(here, doc)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    return p.returncode, p.stdout.decode(errors="replace")


failures = 0
for doc, code, says in (("good.md", 0, "the figures of 'nlsoft-console simulate --rig demo' as quoted (1)"),
                        ("stale-figure.md", 1, "did not print: 95432 B"),
                        ("untold-figure.md", 1, "does not quote (as printed, spacing aside): 3.00 %"),
                        ("partial-figure.md", 1, "did not print: 00 %"),
                        ("stale-output.md", 1, "did not print:\n    nRMSE       3.49 %")):
    got, out = run(doc)
    ok = got == code and says in out
    print(f"{'PASS' if ok else 'FAIL'} {doc}: exit {got} (expected {code}), "
          f"{'says' if says in out else 'does not say'} '{says.splitlines()[0]}'")
    if not ok:
        failures += 1
        print("  " + "\n  ".join(out.strip().splitlines()))
sys.exit(1 if failures else 0)
