"""``python -m bearingfw`` is the ``bearingfw`` command."""

import sys

from bearingfw.cli.main import main

sys.exit(main())
