"""Battery and charger physics for the charge-program simulator."""
