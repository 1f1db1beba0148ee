"""One module per `mtcal` subcommand (see mtcal/cli.py for the contract)."""
