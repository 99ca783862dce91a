#!/usr/bin/python3
"""Write sim/input/fabric_presets.c: the text of every data/fabrics/*.json as a C string, so
that `fabric: {preset: NAME}` reads the shipped file's own bytes with the data reader (its
errors then name data/fabrics/NAME.json and a line and column).  Run it after changing a file
there: tests/test_fabric.c checks that the table equals the files."""
import glob
import json
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def c_string(text):
    out = []
    for line in text.splitlines(keepends=True):
        esc = line.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
        out.append('     "%s"' % esc)
    return "\n".join(out)


def main():
    files = sorted(glob.glob(os.path.join(ROOT, "data", "fabrics", "*.json")))
    rows = []
    for path in files:
        name = os.path.basename(path)[:-5]
        text = open(path, encoding="utf-8").read()
        json.loads(text)  # a file that is not JSON is not shipped
        rows.append('    {"%s", "data/fabrics/%s.json",\n%s},' % (name, name, c_string(text)))
    src = ("/* fabric_presets.c — written by tools/fabric_presets.py from data/fabrics/ (do not\n"
           " * edit): the ten fabrics measured by Wang, Ramamoorthi and O'Brien, \"Data-Driven Elastic\n"
           " * Models for Cloth: Modeling and Measurement\" (SIGGRAPH 2011), as distributed with ARCSim\n"
           " * (docs/fabrics.md has the source and licence). */\n"
           "#include \"scene_fabric.h\"\n\n"
           "const sc_fabric_preset sc_fabric_presets[] = {\n%s\n};\n"
           "const int sc_nfabric_presets = %d;\n") % ("\n".join(rows), len(rows))
    with open(os.path.join(ROOT, "sim", "input", "fabric_presets.c"), "w", encoding="utf-8") as f:
        f.write(src)


if __name__ == "__main__":
    main()
