#!/usr/bin/env python3
"""Pastes `clpt --help` into README.md between its --help markers (test Cli.HelpMatchesReadme
checks they agree). Usage: scripts/update-readme-help.py [path/to/clpt]  (default build/clpt)."""
import pathlib
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
clpt = sys.argv[1] if len(sys.argv) > 1 else str(root / "build" / "clpt")
text = subprocess.run([clpt, "--help"], check=True, capture_output=True, text=True).stdout
readme = root / "README.md"
s = readme.read_text()
begin, end = "<!-- clpt --help begins -->\n```\n", "```\n<!-- clpt --help ends -->"
b, e = s.find(begin), s.find(end)
if b < 0 or e < 0:
    sys.exit("README.md lacks the --help block markers")
readme.write_text(s[: b + len(begin)] + text + s[e:])
print("README.md: --help block updated")
