from regmap.entry import main

raise SystemExit(main())
