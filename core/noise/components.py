"""The radiating parts of the noise chain and the names of their sound powers, in the order outputs list them."""

COMPONENTS = ("rail", "sleeper", "wheel")  # the radiating parts of the noise chain, one sound power each
TOTAL = "total"  # their energetic sum
SOUND_POWER_PARTS = (*COMPONENTS, TOTAL)  # every sound power of a run's noise, in the order outputs list them
