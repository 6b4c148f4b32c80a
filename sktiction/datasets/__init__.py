"""Loop sets: simulated (``make_loops``), measured (``read_loops``, ``read_loop_file``,
``list_loop_files``) and the shipped examples (simulated, and real plant windows)."""

from .._lazy import attach

__getattr__, __dir__, __all__ = attach(
    __name__,
    {
        "._examples": ["load_example"],
        "._generators": ["make_loops"],
        "._measured": ["list_loop_files", "read_loop_file", "read_loops"],
        "._plant_examples": ["load_plant_examples"],
    },
)
