"""``python -m heatdata.cli``: the ``heatdata`` command."""

import sys

from heatdata.cli import main

sys.exit(main())
