"""The warnings ``tune`` gives: what the answer leaves out, or what it holds for only."""


class OtherContactsWarning(UserWarning):
    """Contacts other than the pair's are active at the configuration: the reduced model leaves them out."""


class MassChangeWarning(UserWarning):
    """The effective mass moves by more than ``MASS_CHANGE_WARN`` over the engine's contact."""


class JointLimitWarning(UserWarning):
    """The configuration has a joint outside its limits."""


class UnmodelledSettingWarning(UserWarning):
    """A setting of the MuJoCo model changes the contact's e_N and the answer leaves it out.

    Not given where the engine loop reached the target: its drops run the whole model.
    """
