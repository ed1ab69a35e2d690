"""``python -m contactalpha``: the same as the ``contactalpha`` command."""

import sys

from .cli import main

sys.exit(main())
