"""``python -m sktiction``: the same as the ``sktiction`` command."""

import sys

from .cli import main

sys.exit(main())
