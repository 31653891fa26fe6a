"""`presets`, `data`, `demo`: what is shipped, and the short representative study."""

import json

from ._common import InputError, applicable, get_preset, prepare_out


def cmd_presets(args) -> int:
    from rotorjax import presets

    chosen = [get_preset(args.name)] if args.name else list(presets.PRESETS.values())
    if args.json:
        print(json.dumps([{"name": p.name, "source": p.source, "kind": p.kind, "speed_key": p.speed_key,
                           "time_unit": p.time_unit, "length_unit": p.length_unit, "commands": applicable(p),
                           "parameters": p.info()}
                          for p in chosen], indent=2))
        return 0
    for p in chosen:
        print(f"{p.name}: {p.source}")
        print(f"  kind: {p.kind}; speed: {p.speed_key}; units: time {p.time_unit}, length {p.length_unit}")
        print("  commands: " + ", ".join(applicable(p)))
        if args.name:
            width = max(len(k) for k in p.defaults)
            print(f"  {'key'.ljust(width)}  {'default':>12}  {'unit':14}  {'valid':24}  meaning")
            for row in p.info():
                print(f"  {row['key'].ljust(width)}  {row['default']:>12.6g}  {row['unit']:14}  "
                      f"{row['valid']:24}  {row['meaning']}")
        else:
            for row in p.info():
                print(f"  {row['key']} = {row['default']:g}    {row['meaning']} [{row['unit']}; {row['valid']}]")
    return 0


def cmd_data(args) -> int:
    from rotorjax.identify import DATASETS, dataset_path

    if args.action == "list":
        if args.name:
            raise InputError(f"`rotorjax data list` takes no NAME (got {args.name!r})")
        for name, (_, description) in DATASETS.items():
            print(f"{name}: {description}\n  {dataset_path(name)}")
        return 0
    if not args.name:
        raise InputError(f"`rotorjax data path` needs a NAME: one of {', '.join(DATASETS)}")
    print(dataset_path(args.name))
    return 0


def cmd_demo(args) -> int:
    from rotorjax.demo import run_demo

    prepare_out(args.out)
    run_demo(args.out)
    return 0
