#!/usr/bin/env python
from sneaky_cfg.cfg import SneakyConfig

print(SneakyConfig.defaults)
