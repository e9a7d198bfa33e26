"""``python -m harness …``: the command line of :mod:`harness.cli`, as the ``harness`` script runs it."""

import sys

from harness.cli import main

sys.exit(main())
