"""`draw`: the rotor of a preset or a rotor file, drawn (and its layout as numbers)."""

import json

from ._common import build, out_stem, preset_and_params, prepare_out, save_figure


def _summary(lay) -> str:
    if lay["kind"] != "shaft":
        return {"planar": "a planar rotor (end view)", "machine": "a rigid rotor on two supports",
                "modal": "a pinned-pinned modal shaft with a disk"}[lay["kind"]]
    parts = [f"{len(lay['elements'])} elements ({lay['theory']}), {lay['length']:.6g} m, {lay['mass']:.6g} kg",
             f"{len(lay['materials'])} material{'s' * (len(lay['materials']) != 1)}", f"{len(lay['disks'])} disks",
             f"{len(lay['bearings'])} bearings and seals"]
    parts += [f"{len(lay[k])} {k.replace('_', ' ')}" for k in ("point_masses", "supports") if lay[k]]
    named = [p["table"] for p in lay["components"]]
    if named:
        parts.append("components: " + ", ".join(f"{t} (node {p['node']})" if p["node"] is not None else t
                                                for t, p in zip(named, lay["components"])))
    return "; ".join(parts)


def cmd_draw(args) -> int:
    from rotorjax.plot import rotor, rotor_layout

    preset, params = preset_and_params(args, "draw")
    prepare_out(args.out)
    scene = build(preset, params).scene
    lay = rotor_layout(scene)
    stem = out_stem(args.out, preset, "draw_")
    files = {"plot": stem + ".png", "json": stem + ".json"}
    save_figure(rotor(scene, title=f"{preset.name}: {_summary(lay).split(';')[0]}"), files["plot"])
    out = {"target": preset.name, "unit": "m, kg, Pa, kg/m^3", "layout": lay, "files": files}
    with open(files["json"], "w") as f:
        json.dump(out, f, indent=2)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name}: {_summary(lay)}")
    print(f"  drawn to {files['plot']}; the layout in {files['json']}")
    return 0
