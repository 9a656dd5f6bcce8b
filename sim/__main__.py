import sys

from sim.front.launch import main

sys.exit(main())
