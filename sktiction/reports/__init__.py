"""Reports: batch scans of many loops and plots of one loop's cycles."""

from .._lazy import attach

__getattr__, __dir__, __all__ = attach(
    __name__,
    {
        ".plots": ["plot_loop"],
        ".scan": ["scan_loops"],
        ".html": ["write_html_report"],
        "._stream": ["scan_files"],
        ".valves": ["summarise_valves"],
    },
)
