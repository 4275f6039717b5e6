#!/usr/bin/python3
"""The files a scene reads: superelements (`superelement = ...`) and tables (`file = ...`), relative to the
scene's folder. Used by Makefile.workflow to write make dependencies (scene + its superelements ->
results) and by pipelines/sweep to link a template's inputs next to each generated scene.

    scene_inputs.py SCENE.toml                 # one path per line, as written in the scene
    scene_inputs.py SCENE.toml --make TARGET   # "TARGET: DIR/a.h5 DIR/b.csv" for make's include
"""
import argparse
import sys
import tomllib
from pathlib import Path

INPUT_KEYS = ("superelement", "file")


def scene_inputs(scene: Path) -> list[str]:
    """Paths (as written, relative to the scene's folder) of every file the scene refers to, in order."""
    with open(scene, "rb") as f:
        return inputs_of(tomllib.load(f))


def inputs_of(doc: dict) -> list[str]:
    """The same for a parsed scene."""
    found: list[str] = []

    def walk(node):
        if isinstance(node, dict):
            for key, value in node.items():
                if key in INPUT_KEYS and isinstance(value, str) and value not in found:
                    found.append(value)
                else:
                    walk(value)
        elif isinstance(node, list):
            for item in node:
                walk(item)

    walk(doc)
    return found


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", type=Path)
    ap.add_argument("--make", metavar="TARGET", help="print a make dependency line for TARGET")
    args = ap.parse_args()
    try:
        inputs = scene_inputs(args.scene)
    except (OSError, tomllib.TOMLDecodeError) as e:
        print(f"scene_inputs: {args.scene}: {e}", file=sys.stderr)
        return 1
    if args.make:
        folder = args.scene.parent
        print(f"{args.make}: " + " ".join(str(folder / p) for p in inputs))
    else:
        print("\n".join(inputs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
