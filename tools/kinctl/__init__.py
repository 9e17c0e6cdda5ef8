"""kinctl: the client of kinctld (command line `kinctl`, Python API `kinctl.Client`)."""
__version__ = "0.1.0"


def __getattr__(name):
    # Lazy, so that `kinctl --help` works before the messages are built.
    if name in ("Client", "DaemonNotFound"):
        from kinctl import client
        return getattr(client, name)
    raise AttributeError(name)
