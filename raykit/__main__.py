import sys

from raykit.cli import main

sys.exit(main())
