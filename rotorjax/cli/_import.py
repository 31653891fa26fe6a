"""`import-ross`: a rotor saved by ROSS, written as a rotorjax rotor file."""

import json


def cmd_import_ross(args) -> int:
    from rotorjax.io import import_ross

    out = import_ross(args.file, args.out, args.name)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    e = out["elements"]
    parts = [f"{e['shaft']} shaft elements ({out['theory']}, {e['material']} material{'s' * (e['material'] != 1)})",
             f"{e['disk']} disks", f"{e['bearing']} bearings"]
    parts += [f"{e[k]} {k.replace('_', ' ')}s" for k in ("point_mass", "support") if e[k]]
    print(f"{args.file} (ROSS {out['version']}.x) -> {out['out']}: " + ", ".join(parts))
    for note in out["notes"]:
        print(f"  note: {note}")
    print(f"  next: rotorjax modes {out['out']}")
    return 0
