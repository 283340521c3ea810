"""rikin: robot inverse kinematics, every solution, checked by forward kinematics.

The module behind the course companion's chapters and exercises.

>>> import rikin
>>> arm = rikin.robots.aula10_6r()
>>> T = arm.fk(rikin.rad([99.6, 9, 26.4, 68.4, 30, 151]))
>>> len(arm.ik(T))
8
"""

__version__ = "0.1.0"

from . import i18n, robots, transforms
from .dh import Link, SerialArm
from .errors import (
    IKError,
    InputError,
    NotIndexedError,
    OutOfRangeError,
    RikinError,
    UnreachableError,
)
from .ik import BatchIKResult, Branch, IKResult
from .transforms import (
    deg,
    homogeneous,
    inv_transform,
    r_to_rpy,
    r_to_zyz,
    rad,
    rotx,
    roty,
    rotz,
    rpy_to_r,
    transl,
    wrap_angle,
    zyz_to_r,
)

__all__ = [
    "__version__",
    "i18n",
    "robots",
    "transforms",
    "Link",
    "SerialArm",
    "IKResult",
    "BatchIKResult",
    "Branch",
    "RikinError",
    "InputError",
    "OutOfRangeError",
    "NotIndexedError",
    "IKError",
    "UnreachableError",
    "rotx",
    "roty",
    "rotz",
    "transl",
    "homogeneous",
    "inv_transform",
    "rpy_to_r",
    "r_to_rpy",
    "zyz_to_r",
    "r_to_zyz",
    "wrap_angle",
    "deg",
    "rad",
]
