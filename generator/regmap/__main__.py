from regmap.cli import main

raise SystemExit(main())
