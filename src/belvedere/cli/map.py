"""``belvedere map show MAP.yaml [-o map.png] [--trajectory FILE.tum]``: a map as a picture.

The map is drawn in map_saver's greys (free white, occupied black, unknown grey), small maps
enlarged; a TUM trajectory in the map frame is drawn over it from a green start to a red end.
With ``-o`` the PNG goes there; without, to stdout when it is piped (``> map.png``), else to
``MAP.png`` in the current directory, and the map's summary is printed.
"""

from __future__ import annotations

import argparse
import io
import sys
from pathlib import Path

from belvedere.errors import BelvedereError
from belvedere.fileio import write_file

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("map", parents=[common], help="occupancy maps (map_server's files)")
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)
    show = actions.add_parser(
        "show",
        parents=[common],
        help="draw a map (and a trajectory) as a PNG",
        description="Draw a map_server map as a PNG: free white, occupied black, unknown "
        "grey; with --trajectory, a TUM trajectory in the map frame over it.",
    )
    show.add_argument("map", metavar="MAP.yaml", help="the map's YAML (map_server's format)")
    show.add_argument("-o", "--output", metavar="FILE.png", help="where to write the picture")
    show.add_argument(
        "--trajectory",
        metavar="FILE.tum",
        help="a trajectory to draw (TUM: stamp tx ty tz qx qy qz qw, in the map frame)",
    )
    show.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from belvedere.maps import load_map, map_picture, map_summary, read_tum

    if args.output is not None and Path(args.output).suffix.lower() != ".png":
        msg = f"-o {args.output}: the picture is a PNG; name it FILE.png"
        raise BelvedereError(msg)
    grid = load_map(args.map)
    trajectory = read_tum(args.trajectory) if args.trajectory else None
    picture = map_picture(grid, trajectory=trajectory)
    data = io.BytesIO()
    picture.save(data, format="PNG")
    png = data.getvalue()
    if args.output is None and not sys.stdout.isatty():
        sys.stdout.buffer.write(png)
        sys.stdout.flush()
        return 0
    target = Path(args.output) if args.output else Path(Path(args.map).stem + ".png")
    write_file(target, png)
    summary = map_summary(grid)
    if trajectory is not None:
        summary += f"; {len(trajectory)} poses drawn"
    sys.stderr.write(f"wrote {target} ({picture.width} x {picture.height} px)\n{summary}\n")
    return 0
