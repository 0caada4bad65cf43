"""One module per `overseec` subcommand: ``register(subparsers)`` and ``run(args, progress)``."""
