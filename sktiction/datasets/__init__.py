"""Loop sets: simulated (``make_loops``), measured (``read_loops``, ``read_loop_file``,
``list_loop_files``) and the shipped examples (simulated, and real plant windows)."""

from ._examples import load_example
from ._generators import make_loops
from ._measured import list_loop_files, read_loop_file, read_loops
from ._plant_examples import load_plant_examples

__all__ = [
    "list_loop_files",
    "load_example",
    "load_plant_examples",
    "make_loops",
    "read_loop_file",
    "read_loops",
]
