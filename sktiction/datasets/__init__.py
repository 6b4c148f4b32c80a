"""Loop sets: simulated (``make_loops``), measured (``read_loops``) and the shipped example."""

from ._examples import load_example
from ._generators import make_loops
from ._measured import read_loops

__all__ = ["load_example", "make_loops", "read_loops"]
