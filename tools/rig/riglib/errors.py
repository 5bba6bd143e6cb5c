"""The rig's one error type: a message for the user, printed without a traceback."""


class RigError(Exception):
    pass
