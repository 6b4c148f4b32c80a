"""Reports: batch scans of many loops and plots of one loop's cycles."""

from ._stream import scan_files
from .html import write_html_report
from .plots import plot_loop
from .scan import scan_loops

__all__ = ["plot_loop", "scan_loops", "write_html_report", "scan_files"]
