"""Resolve packages from BELVEDERE_ORACLE_PACKAGES ("name=dir" pairs joined by os.pathsep)."""

import os


def get_package_share_directory(package_name: str) -> str:
    for pair in os.environ.get("BELVEDERE_ORACLE_PACKAGES", "").split(os.pathsep):
        name, _, path = pair.partition("=")
        if name == package_name:
            return path
    raise LookupError(package_name)
