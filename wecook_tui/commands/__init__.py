"""One module per `wecook` subcommand group; each exposes ``register(subparsers)``.

A command's ``run(args) -> int`` returns the exit code. Bad input raises ``InputError``, which the
entry point prints as one line with exit code 2.
"""
