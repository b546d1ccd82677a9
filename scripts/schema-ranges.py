#!/usr/bin/env python3
"""Prints the Markdown table of every numeric scene key's valid range, from the scene
schema (docs/scene.schema.json, or `wave schema` on stdin with `-`): the table in
docs/hardening.md ("Ranges of scene values"), which tests/test_hostile.py keeps equal."""
import json
import sys


def numbers(node, pointer, out):
    for branch in node.get("oneOf", []):
        numbers(branch, pointer, out)
    if node.get("type") in ("number", "integer"):
        out.append((pointer, node))
    for key, child in node.get("properties", {}).items():
        numbers(child, pointer + "/" + key, out)
    if "items" in node:
        numbers(node["items"], pointer + "/*", out)
    return out


def shown(v):
    if isinstance(v, float) and v.is_integer() and abs(v) < 1e17:
        v = int(v)
    if isinstance(v, int) and abs(v) >= 100000:
        return f"{v:.0e}".replace("e+0", "e").replace("e+", "e") if v % 10 ** (len(str(abs(v))) - 1) == 0 else str(v)
    return str(v)


def table(schema):
    rows = ["| key | range | type |", "|---|---|---|"]
    for pointer, n in numbers(schema, "", []):
        lo = ("(" + shown(n["exclusiveMinimum"])) if "exclusiveMinimum" in n else ("[" + shown(n["minimum"]))
        hi = (shown(n["exclusiveMaximum"]) + ")") if "exclusiveMaximum" in n else (shown(n["maximum"]) + "]")
        rows.append(f"| `{pointer}` | {lo}, {hi} | {n['type']} |")
    return "\n".join(rows) + "\n"


if __name__ == "__main__":
    source = sys.stdin if sys.argv[1:] == ["-"] else open(sys.argv[1] if sys.argv[1:] else "docs/scene.schema.json")
    sys.stdout.write(table(json.load(source)))
