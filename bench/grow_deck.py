#!/usr/bin/env python3
"""Grow a COMGEOM (GIFT v5) deck into a larger one: NX x NY copies of it
side by side in x and y, optionally standing on a ground half-space.

`check` is compared with BRL-CAD's gqa on the shared decks (20 to 282
bodies); users' vehicle decks hold a thousand bodies or more and often a
ground plane. This makes such a deck from a shared one, so that both
programs can be timed on it (BENCHMARKS.md, "`check` at gqa's grid"):

    bench/grow_deck.py ../shared/decks/comgeom/mep021a-generator-v5.cg 2 2 \
        --step 900 620 --ground --ground-z -359.087 > gen4.cg
    comgeom-g -v5 gen4.cg gen4.g

Copy (i, j) is the deck moved by (i * DX, j * DY, 0) in its own units
(`--step DX DY`, or by default the extent of its boxes and polyhedra plus
`--gap`), with its bodies, regions and idents renumbered after the
copies before it. `--ground` adds a body and region GROUND: a half-space
`HAF 0 0 1 d`, z below `--ground-z` (by default the lowest corner of the
deck's boxes and polyhedra).
Only bodies whose points can be moved field by field are read (RPP, BOX,
RAW, ARB4-ARB8, SPH, ELL, RCC, REC, TRC, TEC, TGC, TOR, HAF); anything
else stops with the line it is on. Standard library only.
"""
import argparse
import sys

# Per body type: which of its numbers (in card order) are points.
POINTS = {
    "RCC": [0], "REC": [0], "TRC": [0], "TEC": [0], "TGC": [0], "TOR": [0],
    "SPH": [0], "BOX": [0], "RAW": [0], "ELL": [0, 3],
    **{f"ARB{n}": [3 * k for k in range(n)] for n in range(4, 9)},
}
FIELD = 10


def fail(line_no, text):
    sys.exit(f"grow_deck: line {line_no}: {text}")


def body_cards(lines, start, count):
    """The cards of `count` bodies from line `start` on: (first line, cards)."""
    bodies, at = [], start
    while len(bodies) < count:
        if at >= len(lines):
            fail(at + 1, f"the deck ends after {len(bodies)} of {count} bodies")
        cards = [lines[at]]
        at += 1
        # A continuation card leaves the type blank (some decks repeat
        # the body's number on it).
        number = cards[0][:5].strip()
        while (
            at < len(lines)
            and lines[at].strip()
            and not lines[at][5:10].strip()
            and lines[at][:5].strip() in ("", number)
        ):
            cards.append(lines[at])
            at += 1
        bodies.append((at - len(cards) + 1, cards))
    return bodies, at


def integer(line_no, text, what):
    """`text` (a field of the card on line `line_no`) as an integer, blank as 0."""
    try:
        return int(text.strip() or 0)
    except ValueError:
        fail(line_no, f"{text.strip()!r} is not a whole number ({what})")


def numbers(line_no, cards):
    values = []
    for n, card in enumerate(cards):
        for k in range(6):
            field = card[10 + FIELD * k:10 + FIELD * (k + 1)].strip()
            try:
                values.append(float(field) if field else None)
            except ValueError:
                fail(line_no + n, f"{field!r} in columns {11 + FIELD * k}-{10 + FIELD * (k + 1)} "
                     "is not a number (a GIFT v5 body card has six 10-column fields)")
    return values


def moved_fields(line_no, kind):
    """The numbers of a `kind` body that a move adds to, each with its axis
    (a HAF's distance is worked out from its normal instead)."""
    if kind == "RPP":
        return [(k, k // 2) for k in range(6)]
    if kind in POINTS:
        return [(first + k, k) for first in POINTS[kind] for k in range(3)]
    if kind == "HAF":
        return []
    fail(line_no, f"body type {kind} is not one this script can move")


def moved(kind, values, fields, offset):
    values = list(values)
    for k, axis in fields:
        values[k] += offset[axis]
    if kind == "HAF":
        # The solid is N.x <= -d: moved by o, d becomes d - N.o.
        values[3] -= sum(values[k] * offset[k] for k in range(3))
    return values


def card_text(head, values, tail):
    fields = "".join(f"{v:<{FIELD}.4f}" if v is not None else " " * FIELD for v in values)
    return head + fields + tail


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("deck")
    ap.add_argument("nx", type=int)
    ap.add_argument("ny", type=int)
    ap.add_argument("--gap", type=float, default=10.0, help="space between copies (deck units)")
    ap.add_argument("--step", type=float, nargs=2, metavar=("DX", "DY"),
                    help="distance from copy to copy instead (deck units)")
    ap.add_argument("--ground", action="store_true", help="add a ground half-space under the copies")
    ap.add_argument("--ground-z", type=float, metavar="Z",
                    help="the ground's top (default: the lowest corner of the boxes and polyhedra)")
    args = ap.parse_args()
    lines = open(args.deck).read().split("\n")
    counts = lines[1].split() if len(lines) > 1 else []
    if len(counts) < 2:
        fail(2, "expected the numbers of bodies and regions (GIFT v5)")
    if not lines[1][:10].strip():
        fail(2, "the counts are where GIFT v4 puts them: only v5 decks are read "
             "(their body cards' columns differ)")
    n_bodies, n_regions = (
        integer(2, count, "the numbers of bodies and regions") for count in counts[:2]
    )
    bodies, at = body_cards(lines, 2, n_bodies)
    regions = []
    while at < len(lines) and lines[at].strip() != "-1":
        regions.append((at + 1, lines[at]))
        at += 1
    if at == len(lines):
        fail(at, "no -1 card ends the region table")
    idents = [(k + 1, line) for k, line in enumerate(lines) if k > at and line.strip()]

    lo, hi = [float("inf")] * 3, [float("-inf")] * 3
    parsed = []
    for line_no, cards in bodies:
        kind = cards[0][5:10].strip().upper()
        values = numbers(line_no, cards)
        fields = moved_fields(line_no, kind)
        read = [k for k, _ in fields] + ([0, 1, 2, 3] if kind == "HAF" else [])
        if any(k >= len(values) or values[k] is None for k in read):
            fail(line_no, f"{kind} body {cards[0][:5].strip()} is missing a number "
                 f"({len(cards)} card(s) with {sum(v is not None for v in values)} numbers)")
        parsed.append((line_no, cards, kind, values, fields))
        if kind == "RPP":
            corners = [values[0:6:2], values[1:6:2]]
        elif kind in POINTS and kind.startswith("ARB"):
            corners = [values[3 * k:3 * k + 3] for k in range(int(kind[3]))]
        else:
            continue
        for point in corners:
            for k in range(3):
                lo[k], hi[k] = min(lo[k], point[k]), max(hi[k], point[k])
    if lo[0] > hi[0]:
        sys.exit("grow_deck: no RPP or ARB body to size the copies by")
    # Bodies given by a vertex and vectors are sized by their vertex only:
    # the gap keeps copies apart where they reach further.
    step = args.step or [hi[0] - lo[0] + args.gap, hi[1] - lo[1] + args.gap]

    copies = [(i * step[0], j * step[1], 0.0) for j in range(args.ny) for i in range(args.nx)]
    out_bodies, out_regions, out_idents = [], [], []
    for c, offset in enumerate(copies):
        for line_no, cards, kind, values, fields in parsed:
            new = moved(kind, values, fields, offset)
            number = int(cards[0][:5]) + c * n_bodies
            for n, card in enumerate(cards):
                # The number as the deck writes it (to the left or the
                # right of its field), on each card that has it.
                label = f"{number:<5d}" if card[:1].strip() else f"{number:>5d}"
                label = label if card[:5].strip() else " " * 5
                head = label + card[5:10]
                out_bodies.append(card_text(head, new[6 * n:6 * n + 6], card[70:]))
        for line_no, card in regions:
            region = integer(line_no, card[:5], "a region number, columns 1-5")
            fields = []
            for k in range(9):
                field = card[6 + 7 * k:13 + 7 * k]
                op = field[:2]
                number = integer(line_no, field[2:], f"a body number, columns {9 + 7 * k}-{13 + 7 * k}")
                shift = n_regions if op[1:].lower() == "g" else n_bodies
                if number:
                    number += c * shift if number > 0 else -c * shift
                fields.append(f"{op:2s}{number:5d}")
            head = f"{region + c * n_regions:5d}" if region else " " * 5
            out_regions.append(head + " " + "".join(fields) + card[69:])
        for line_no, card in idents:
            region = integer(line_no, card[:5], "a region number, columns 1-5")
            ident = integer(line_no, card[5:10], "an ident, columns 6-10")
            ident = ident + c * n_regions if ident else 0
            out_idents.append(f"{region + c * n_regions:<5d}{ident:<5d}" + card[10:])
    total_bodies, total_regions = len(copies) * n_bodies, len(copies) * n_regions
    if args.ground:
        total_bodies += 1
        total_regions += 1
        d = -(lo[2] if args.ground_z is None else args.ground_z)
        out_bodies.append(card_text(f"{total_bodies:<5d}HAF  ", [0.0, 0.0, 1.0, d], " " * 20 + "GROUND"))
        out_regions.append(f"{total_regions:5d}   {total_bodies:5d}" + f"  {0:5d}" * 8 + "GROUND")
        out_idents.append(f"{total_regions:<5d}{total_regions:<5d}0    9    100  GROUND")
    print(lines[0])
    print(f"{total_bodies:<5d}{total_regions:<5d}")
    print("\n".join(out_bodies + out_regions + ["-1"] + out_idents))


if __name__ == "__main__":
    main()
