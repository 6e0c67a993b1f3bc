#!/usr/bin/env python
"""Imports the package's generated config module: it must fail, its .cfg imports os."""

import sneaky_cfg.cfg.SneakyConfig  # type: ignore[import-not-found]  # noqa: F401
