"""Loop sets: simulated (``make_loops``), measured (``read_loops``, ``read_loop_file``,
``list_loop_files``) and the shipped example."""

from ._examples import load_example
from ._generators import make_loops
from ._measured import list_loop_files, read_loop_file, read_loops

__all__ = ["list_loop_files", "load_example", "make_loops", "read_loop_file", "read_loops"]
