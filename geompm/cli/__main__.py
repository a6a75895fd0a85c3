"""``python -m geompm.cli ...``, as the ``geompm`` command (the study's workers start runs this way)."""

import sys

from geompm.cli.main import main

sys.exit(main())
