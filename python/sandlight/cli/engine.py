"""Commands of the transport engine: reflectance, demo."""

from sandlight.cli._app import app


@app.command()
def version() -> None:
    """Print the sandlight version."""
    import sandlight

    print(sandlight.__version__)
