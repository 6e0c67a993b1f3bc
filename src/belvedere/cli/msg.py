"""``belvedere msg show|list|md5|package|packages`` — rosmsg, from belvedere's type store."""

from __future__ import annotations

import argparse

from belvedere.cli._typetool import add_type_parser

__all__ = ["add_parser"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    add_type_parser(sub, common, "msg")
