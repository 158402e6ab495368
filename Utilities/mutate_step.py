#!/usr/bin/env python3
"""Deterministic mutation corpus of STEP files, for the reader's robustness tests and fuzzing.

  python3 Utilities/mutate_step.py OUT_DIR SEED.step [SEED.step ...] [--per-seed N] [--seed S]

Writes N variants of every seed (default 80) into OUT_DIR, named
<seed>-<index>-<class>.step, and a manifest (manifest.tsv: file, seed, class, detail). The same
arguments always give the same files. The classes are the faults users' files and a mutation
fuzzer produce: bit flips, truncation (with the terminator put back), deleted and duplicated
entities, dangling, wrong-type, same-type and self references, non-finite and absurd numbers,
negative radii, zero-length edges, deep parentheses, emptied lists, a list's item dropped,
changed enumerations, B-spline data that contradict themselves, invalid UTF-8, an entity of
several megabytes.
"""
import argparse
import os
import random
import re
import sys

ENTITY = re.compile(rb"^#(\d+)\s*=\s*([A-Z_0-9]*)", re.M)
REF = re.compile(rb"#(\d+)")
REAL = re.compile(rb"(?<![#\w.])-?\d+\.\d*(?:E[+-]?\d+)?")
RADIUS_TYPES = (b"CIRCLE", b"CYLINDRICAL_SURFACE", b"SPHERICAL_SURFACE", b"TOROIDAL_SURFACE",
                b"CONICAL_SURFACE")
BAD_NUMBERS = (b"NAN", b"INF", b"-INF", b"1.E308", b"1.7976931348623157E308", b"1.E99999",
               b"-1.E-99999", b"1.E+400", b"1.E12", b"-1.E15")


def statements(data):
    """(start, end, id, type) of every entity statement of the data section."""
    out = []
    for m in ENTITY.finditer(data):
        end = data.find(b";", m.end())
        # A ';' inside a string would end the statement early; good enough for seeds we write.
        if end < 0:
            break
        out.append((m.start(), end + 1, int(m.group(1)), m.group(2)))
    return out


def terminate(data):
    if b"END-ISO-10303-21;" not in data[-64:]:
        data = data.rstrip() + b"\nENDSEC;\nEND-ISO-10303-21;\n"
    return data


def bit_flip(data, rng):
    b = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        i = rng.randrange(len(b))
        b[i] ^= 1 << rng.randrange(8)
    return bytes(b), "bit flips"


def truncate(data, rng):
    body = data.find(b"DATA;")
    cut = rng.randrange(body + 5, len(data) - 40)
    return terminate(data[:cut] + b"\n"), "cut at byte %d" % cut


def delete_entity(data, rng, kinds=(b"CARTESIAN_POINT", b"DIRECTION", b"VECTOR", b"")):
    st = statements(data)
    want = rng.choice(kinds)
    pool = [s for s in st if not want or s[3] == want] or st
    s = rng.choice(pool)
    return data[:s[0]] + data[s[1]:].lstrip(b"\n"), "deleted #%d %s" % (s[2], s[3].decode())


def duplicate_entity(data, rng):
    st = statements(data)
    s = rng.choice(st)
    other = rng.choice(st)
    # Same number, other body: #a = <body of b>
    body = data[other[0]:other[1]]
    body = re.sub(rb"^#\d+", b"#%d" % s[2], body)
    return data[:s[1]] + b"\n" + body + data[s[1]:], "#%d defined twice" % s[2]


def retarget(data, rng, how):
    st = statements(data)
    ids = [s[2] for s in st]
    types = {s[2]: s[3] for s in st if s[3]}
    by_type = {}
    for i, kind in types.items():
        by_type.setdefault(kind, []).append(i)
    for _ in range(50):
        s = rng.choice(st)
        text = data[s[0]:s[1]]
        refs = list(REF.finditer(text, 1))
        refs = [r for r in refs if r.start() > 0]
        if not refs:
            continue
        r = rng.choice(refs)
        if how == "dangling":
            new = max(ids) + rng.randint(1, 1000)
        elif how == "self":
            new = s[2]
        elif how == "same":
            # Another entity of the target's own type: a vertex, an edge, a loop, a surface
            # or a point that belongs elsewhere (well typed, topologically wrong).
            kind = types.get(int(r.group(1)))
            same = [i for i in by_type.get(kind, ()) if i not in (int(r.group(1)), s[2])]
            if not kind or not same:
                continue
            new = rng.choice(same)
        else:
            new = rng.choice(ids)
        a = s[0] + r.start()
        b = s[0] + r.end()
        return data[:a] + b"#%d" % new + data[b:], "#%d: %s -> #%d" % (s[2], r.group(0).decode(), new)
    return bit_flip(data, rng)


def bad_number(data, rng):
    st = [s for s in statements(data) if s[3] in (b"CARTESIAN_POINT", b"DIRECTION") + RADIUS_TYPES]
    s = rng.choice(st)
    text = data[s[0]:s[1]]
    reals = list(REAL.finditer(text))
    if not reals:
        return bit_flip(data, rng)
    r = rng.choice(reals)
    v = rng.choice(BAD_NUMBERS)
    a, b = s[0] + r.start(), s[0] + r.end()
    return data[:a] + v + data[b:], "#%d %s: %s -> %s" % (s[2], s[3].decode(), r.group(0).decode(), v.decode())


def negative_radius(data, rng):
    st = [s for s in statements(data) if s[3] in RADIUS_TYPES]
    if not st:
        return bad_number(data, rng)
    s = rng.choice(st)
    text = data[s[0]:s[1]]
    reals = list(REAL.finditer(text))
    r = reals[-1] if s[3] != b"TOROIDAL_SURFACE" else rng.choice(reals[-2:])
    a, b = s[0] + r.start(), s[0] + r.end()
    val = r.group(0).lstrip(b"-")
    # A cone's last number is its semi-angle, not its radius.
    what = "semi-angle" if s[3] == b"CONICAL_SURFACE" else "radius"
    return data[:a] + b"-" + val + data[b:], "#%d %s %s -%s" % (s[2], s[3].decode(), what, val.decode())


def zero_length_edge(data, rng):
    st = [s for s in statements(data) if s[3] == b"EDGE_CURVE"]
    if not st:
        return delete_entity(data, rng)
    s = rng.choice(st)
    text = data[s[0]:s[1]]
    refs = [r for r in REF.finditer(text) if r.start() > 0]
    if len(refs) < 2:
        return bit_flip(data, rng)
    v1, v2 = refs[0], refs[1]
    a, b = s[0] + v2.start(), s[0] + v2.end()
    return data[:a] + v1.group(0) + data[b:], "#%d EDGE_CURVE ends at one vertex" % s[2]


def empty_list(data, rng):
    """A list among an entity's parameters emptied: '(a,b,c)' -> '()' (a writer that lost a
    B-spline's knots or weights, a shell's faces, a loop's edges)."""
    st = statements(data)
    for _ in range(50):
        s = rng.choice(st)
        text = data[s[0]:s[1]]
        first = text.find(b"(")
        # The innermost lists after the entity's own parenthesis, not empty already.
        lists = [m for m in re.finditer(rb"\(([^()']+)\)", text) if m.start() > first]
        if not lists:
            continue
        m = rng.choice(lists)
        a, b = s[0] + m.start(), s[0] + m.end()
        return data[:a] + b"()" + data[b:], "#%d %s: a list of %d items emptied" % (
            s[2], s[3].decode(), m.group(1).count(b",") + 1)
    return bit_flip(data, rng)


def drop_item(data, rng):
    """One item dropped from a list among an entity's parameters: a point that lost a
    coordinate, a loop an edge, a B-spline a knot."""
    st = statements(data)
    for _ in range(50):
        s = rng.choice(st)
        text = data[s[0]:s[1]]
        first = text.find(b"(")
        lists = [m for m in re.finditer(rb"\(([^()']+)\)", text)
                 if m.start() > first and b"," in m.group(1)]
        if not lists:
            continue
        m = rng.choice(lists)
        items = m.group(1).split(b",")
        k = rng.randrange(len(items))
        a, b = s[0] + m.start(), s[0] + m.end()
        new = b"(" + b",".join(items[:k] + items[k + 1:]) + b")"
        return data[:a] + new + data[b:], "#%d %s: item %d of %d dropped" % (
            s[2], s[3].decode(), k + 1, len(items))
    return bit_flip(data, rng)


ENUM = re.compile(rb"\.[A-Z_][A-Z0-9_]*\.")
ENUM_VALUES = (b".T.", b".F.", b".U.", b".UNSPECIFIED.", b".PCURVE_S1.", b".PCURVE_S2.",
               b".CURVE_3D.", b".PIECEWISE_BEZIER_KNOTS.", b".X.", b".METRE.")


def enumeration(data, rng):
    """An enumeration value changed: an edge or face turned round (.T. <-> .F.), a seam's
    master representation, a B-spline's knot type, or a value no schema has."""
    st = statements(data)
    for _ in range(50):
        s = rng.choice(st)
        text = data[s[0]:s[1]]
        values = list(ENUM.finditer(text))
        if not values:
            continue
        m = rng.choice(values)
        v = rng.choice([e for e in ENUM_VALUES if e != m.group(0)])
        a, b = s[0] + m.start(), s[0] + m.end()
        return data[:a] + v + data[b:], "#%d %s: %s -> %s" % (
            s[2], s[3].decode(), m.group(0).decode(), v.decode())
    return bit_flip(data, rng)


BSPLINE_DEGREE = re.compile(rb"B_SPLINE_(?:CURVE|SURFACE)(?:_WITH_KNOTS)?\s*\(\s*(?:'[^']*'\s*,\s*)?(\d+)")


def bspline_data(data, rng):
    """A B-spline's data made to contradict itself: its degree, or one item of its knots,
    multiplicities or weights raised, lowered, swapped with the next, repeated, dropped, zeroed
    or negated (a writer's off-by-one, knots out of order)."""
    st = [s for s in statements(data) if b"WITH_KNOTS" in data[s[0]:s[1]]]
    for _ in range(50):
        if not st:
            break
        s = rng.choice(st)
        text = data[s[0]:s[1]]
        if rng.random() < 0.25:
            m = BSPLINE_DEGREE.search(text)
            if not m:
                continue
            d = int(m.group(1))
            v = rng.choice([0, d - 1, d + 1, d + 2, 26])
            a, b = s[0] + m.start(1), s[0] + m.end(1)
            return data[:a] + b"%d" % v + data[b:], "#%d: degree %d -> %d" % (s[2], d, v)
        lists = [m for m in re.finditer(rb"\(([^()#']+)\)", text) if re.search(rb"\d", m.group(1))]
        if not lists:
            continue
        m = rng.choice(lists)
        items = [x.strip() for x in m.group(1).split(b",")]
        k = rng.randrange(len(items))
        op = rng.choice(("raise", "lower", "swap", "repeat", "drop", "zero", "negate"))
        try:
            v = float(items[k])
        except ValueError:
            continue
        whole = not re.search(rb"[.Ee]", items[k])
        if op == "raise":
            items[k] = b"%d" % (int(v) + 1) if whole else repr(v + 1.0).encode()
        elif op == "lower":
            items[k] = b"%d" % (int(v) - 1) if whole else repr(v - 0.5).encode()
        elif op == "swap" and len(items) > 1:
            j = k + 1 if k + 1 < len(items) else k - 1
            items[k], items[j] = items[j], items[k]
        elif op == "repeat":
            items.insert(k, items[k])
        elif op == "drop" and len(items) > 1:
            del items[k]
        elif op == "zero":
            items[k] = b"0" if whole else b"0."
        elif op == "negate":
            items[k] = b"%d" % -int(v) if whole else repr(-v).encode()
        a, b = s[0] + m.start(1), s[0] + m.end(1)
        return data[:a] + b",".join(items) + data[b:], "#%d: item %d of a list of %d, %s" % (
            s[2], k + 1, m.group(1).count(b",") + 1, op)
    return bit_flip(data, rng)


def deep_parentheses(data, rng):
    st = statements(data)
    s = rng.choice(st)
    depth = rng.choice((100, 1000, 100000))
    ins = b"#%d = CARTESIAN_POINT('',%s0.%s);\n" % (max(x[2] for x in st) + 1, b"(" * depth, b")" * depth)
    return data[:s[1]] + b"\n" + ins + data[s[1]:], "%d nested parentheses" % depth


def invalid_utf8(data, rng):
    b = bytearray(data)
    i = rng.randrange(data.find(b"DATA;"), len(b) - 30)
    seq = rng.choice((b"\xc3\x28", b"\xff\xfe", b"\xe2\x82", b"\x80"))
    return bytes(b[:i]) + seq + bytes(b[i:]), "bytes %s at %d" % (seq.hex(), i)


def huge_line(data, rng):
    st = statements(data)
    n = 1_000_000
    nums = b",".join(b"%d." % rng.randrange(1000) for _ in range(n))
    ins = b"#%d = CARTESIAN_POINT('',(%s));\n" % (max(x[2] for x in st) + 1, nums)
    return data[:st[-1][1]] + b"\n" + ins + data[st[-1][1]:], "an entity of %d numbers" % n


CLASSES = [
    ("bitflip", bit_flip, 14),
    ("truncate", truncate, 8),
    ("delete-point", lambda d, r: delete_entity(d, r, (b"CARTESIAN_POINT",)), 8),
    ("delete-direction", lambda d, r: delete_entity(d, r, (b"DIRECTION", b"VECTOR")), 6),
    ("delete-any", lambda d, r: delete_entity(d, r, (b"",)), 6),
    ("duplicate", duplicate_entity, 4),
    ("dangling-ref", lambda d, r: retarget(d, r, "dangling"), 6),
    ("wrong-type-ref", lambda d, r: retarget(d, r, "wrong"), 10),
    ("self-ref", lambda d, r: retarget(d, r, "self"), 4),
    ("same-type-ref", lambda d, r: retarget(d, r, "same"), 6),
    ("bad-number", bad_number, 10),
    ("negative-radius", negative_radius, 4),
    ("zero-length-edge", zero_length_edge, 3),
    ("deep-parentheses", deep_parentheses, 2),
    ("empty-list", empty_list, 6),
    ("drop-item", drop_item, 6),
    ("enumeration", enumeration, 6),
    ("bspline-data", bspline_data, 6),
    ("invalid-utf8", invalid_utf8, 4),
]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("seeds", nargs="+")
    ap.add_argument("--per-seed", type=int, default=80)
    ap.add_argument("--seed", type=int, default=20261201)
    ap.add_argument("--huge", action="store_true", help="also one variant with an entity of 1M numbers")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    weights = [c[2] for c in CLASSES]
    rows = []
    for seed_path in args.seeds:
        with open(seed_path, "rb") as f:
            seed = f.read()
        name = os.path.splitext(os.path.basename(seed_path))[0]
        rng = random.Random("%d:%s" % (args.seed, name))
        for k in range(args.per_seed):
            cls, fn, _ = rng.choices(CLASSES, weights)[0]
            data, detail = fn(seed, rng)
            out = os.path.join(args.out, "%s-%03d-%s.step" % (name, k, cls))
            with open(out, "wb") as f:
                f.write(data)
            rows.append((os.path.basename(out), name, cls, detail))
        if args.huge and seed_path == args.seeds[0]:
            data, detail = huge_line(seed, rng)
            out = os.path.join(args.out, "%s-huge-line.step" % name)
            with open(out, "wb") as f:
                f.write(data)
            rows.append((os.path.basename(out), name, "huge-line", detail))
    with open(os.path.join(args.out, "manifest.tsv"), "w") as f:
        f.write("file\tseed\tclass\tdetail\n")
        for r in rows:
            f.write("\t".join(r) + "\n")
    print("%d variants of %d seeds in %s" % (len(rows), len(args.seeds), args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
