"""AUTO-07p equation files, constants and the driver that runs them (see `driver`)."""
