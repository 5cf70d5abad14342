#!/usr/bin/env python3
"""Counts the lines of unsafe Rust under crates/ (or the folders given): every line from an
`unsafe {` block, `unsafe fn` or `unsafe impl` to its closing brace, comments and blank lines
left out, and the unsafe blocks themselves. Prints one line per crate and a total."""
import pathlib
import re
import sys

UNSAFE_START = re.compile(r"\bunsafe\s*(\{|fn\b|impl\b|extern\b)")


def code_lines(text):
    """The lines of `text` with comments and string contents blanked, so braces count right."""
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    text = re.sub(r'"(\\.|[^"\\])*"', '""', text)
    return text.split("\n")


def unsafe_lines(path):
    lines = code_lines(path.read_text())
    counted, blocks, depth_at_start, depth = set(), 0, None, 0
    for number, line in enumerate(lines):
        if depth_at_start is None and UNSAFE_START.search(line):
            depth_at_start, blocks = depth, blocks + 1
        for char in line:
            depth += {"{": 1, "}": -1}.get(char, 0)
        if depth_at_start is not None:
            if line.strip():
                counted.add(number)
            if depth <= depth_at_start and "{" in "".join(lines[n] for n in counted if n <= number):
                depth_at_start = None
    return len(counted), blocks


def main():
    roots = [pathlib.Path(p) for p in sys.argv[1:]] or sorted(pathlib.Path("crates").iterdir())
    total_lines = total_blocks = 0
    for root in roots:
        files = sorted(root.rglob("*.rs")) if root.is_dir() else [root]
        lines, blocks = map(sum, zip(*(unsafe_lines(f) for f in files))) if files else (0, 0)
        if lines:
            print(f"{root}: {lines} lines in {blocks} unsafe items")
        total_lines, total_blocks = total_lines + lines, total_blocks + blocks
    print(f"total: {total_lines} lines in {total_blocks} unsafe items")


if __name__ == "__main__":
    main()
