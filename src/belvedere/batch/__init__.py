"""Many runs: a spec → run descriptions → local processes or Ray tasks → rows.

:func:`read_spec` checks a ``belvedere batch`` spec and lists its runs;
:func:`execute_run` runs one (a headless ``belvedere sim``/``launch`` process on a graph of
its own) into its row; :func:`run_local` and :func:`run_ray` run them all;
:func:`write_csv` and :func:`plot_rows` write what they gave.
"""

from belvedere.batch._execute import Row, execute_run
from belvedere.batch._measure import Measure, parse_measure
from belvedere.batch._report import Progress, plot_rows, write_csv
from belvedere.batch._schedule import map_local, map_ray, run_local, run_ray
from belvedere.batch._spec import BatchSpec, RunDescription, read_spec

__all__ = [
    "BatchSpec",
    "Measure",
    "Progress",
    "Row",
    "RunDescription",
    "execute_run",
    "map_local",
    "map_ray",
    "parse_measure",
    "plot_rows",
    "read_spec",
    "run_local",
    "run_ray",
    "write_csv",
]
