"""Sub-commands of the ``wheelrail`` command line, one module each (see ``wheelrail.cli.dispatch``)."""
