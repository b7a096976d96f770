"""Allow `python -m obstacle_fusion`."""

from obstacle_fusion.cli import main

raise SystemExit(main())
