"""Command-line helpers outside the workflow (``python -m simpick.cli.<name>``).

They sit above every other layer because they read a study's config the way the Snakefile does,
through :func:`simpick.config.read_study` (merged files, duplicate keys refused, every value checked,
defaults filled in), and then call one study function below. A helper never reads a config file by
itself, so a key the workflow would refuse is refused here with the same line.
"""
