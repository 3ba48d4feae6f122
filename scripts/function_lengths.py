#!/usr/bin/env python3
"""Lists the functions of the libraries (msd, io, leg, reference_fem, benchmarks)
longer than a limit, and exits 1 if there is any.

A function is a definition that starts at column 0 (or, inside a namespace, is
not indented past it) with its opening brace at the end of a line, and ends at
the first closing brace at the same indentation. Lambdas and class bodies are
counted inside their function. Usage: function_lengths.py ROOT [LIMIT]."""
import pathlib
import re
import sys

LIBRARIES = ["msd/src", "io/src", "leg/src", "reference_fem/src", "benchmarks/src"]
NOT_A_FUNCTION = re.compile(r"^\s*(namespace|struct|class|enum|union|extern)\b|=\s*\{$|^\s*(const\s+)?(static\s+)?"
                            r"(std::)?(map|vector|set|array)<")


def functions(path):
    lines = path.read_text().split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        if line and not line.startswith((" ", "\t", "#", "/", "}", "template")) and not NOT_A_FUNCTION.search(line):
            # the signature may go on over indented lines up to the opening brace
            k = i
            while k < len(lines) and not lines[k].rstrip().endswith(("{", ";", "}")) and k - i < 8:
                k += 1
            if k < len(lines) and lines[k].rstrip().endswith("{") and "=" not in lines[k].split("(")[0]:
                j = k + 1
                while j < len(lines) and not lines[j].startswith("}"):
                    j += 1
                yield line.strip(), i + 1, j - i + 1
                i = j
        i += 1


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    limit = int(sys.argv[2]) if len(sys.argv) > 2 else 150
    long_ones = []
    for lib in LIBRARIES:
        for path in sorted((root / lib).rglob("*")):
            if path.suffix not in (".cpp", ".cc"):
                continue
            for name, line, length in functions(path):
                if length > limit:
                    long_ones.append((length, f"{path.relative_to(root)}:{line}", name))
    for length, where, name in sorted(long_ones, reverse=True):
        print(f"{length:5d} lines  {where}  {name}")
    if long_ones:
        print(f"{len(long_ones)} function(s) over {limit} lines")
        return 1
    print(f"no function over {limit} lines in {', '.join(LIBRARIES)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
