"""Named numerical tolerances, so no magic number sits in the middle of the code.

All are absolute unless said otherwise. See the conventions page of the book.
"""

from __future__ import annotations

#: How far ``R.T @ R`` may be from the identity (max abs entry) for ``R`` to be
#: accepted as a rotation matrix at the public boundary. Lessons print
#: matrices with 4 decimals, so a looser check would accept garbage and a
#: tighter one would reject the lessons' own numbers.
ORTHONORMAL_TOL = 1e-3

#: A rotation block whose columns are orthonormal to within this (max abs entry
#: of ``R^T R - I``) is used as it is; between this and ``ORTHONORMAL_TOL`` (a
#: rounded or float32 matrix) IK replaces it by the nearest rotation and reports
#: the distance.
ROTATION_CLEAN_TOL = 1e-12

#: A 5-DOF arm (PPRRR, RPRRR) reaches only a 5-dimensional set of poses: its
#: wrist centre must lie where joints 1-2 can put it; any arm's wrist centre
#: (or the point its positioning links place) must lie within their reach. A
#: target whose wrist centre is within this of that set (times the larger of
#: the arm's size and the wrist centre's distance from the base) is a rounded
#: reachable pose, and IK solves the nearest reachable pose and reports the
#: distance; further off it is unreachable. Printed with 4 decimals, the
#: lessons' poses are at most ~3e-5 off (float32: ~4e-8), so this accepts them
#: with 3x margin (as ``ORTHONORMAL_TOL`` does their rotations), and refuses an
#: error of 1e-2 at the lessons' scale (~5e-4).
ROUNDED_POSE_TOL = 1e-4

#: Lengths rikin handles (absolute value, the arm's units): link lengths and
#: offsets, base, tool and target positions, prismatic joint values. Beyond
#: them the formulas' squares and products overflow or underflow double
#: precision (which spans about 1e-308 to 1e308).
MAX_LENGTH = 1e100
MIN_LENGTH = 1e-100

#: IK takes targets, bases and tools within this many times the arm's size of the world
#: origin. Double precision places a point at distance D only to ~1e-16 D, and an IK
#: answer is checked to ``FK_CHECK_TOL`` of the arm's size: at 1e6 sizes the rounding is
#: ~2e-10 of the size, with room for the few dozen roundings of FK and IK; at 1e16 it
#: would be more than the arm itself (a slide's joint value that far is known to ~2).
MAX_DISTANCE_RATIO = 1e6

#: A point closer than this (times the arm's size) to a joint axis is on it,
#: and an elbow this close (relative) to stretched or folded is exactly so:
#: the singular families start where the target's own rounding (~1e-16 of its
#: size) could put it on either side. Further away every branch is solved.
AXIS_TOL = 1e-13

#: A sine below this (in absolute value) counts as zero: the wrist (sin q5),
#: the elbow (sin of the elbow angle) or the shoulder (distance of the wrist
#: centre from axis 1, relative to the arm's size) is singular there.
SINGULAR_TOL = 1e-9

#: Relative slack on a reach limit: a target this close (times the arm's
#: size) beyond the boundary is clamped onto it instead of rejected, so that
#: FK of a stretched arm is solved and not refused for rounding.
REACH_TOL = 1e-9

#: When the distance from the shoulder to the target of a two-link chain is
#: within this (times L2 + L3) of the longest or shortest it reaches, the elbow
#: is taken as exactly stretched or folded. The rounding of a stretched arm's
#: target would otherwise come out as an elbow angle of ~1e-8 rad, enough to
#: hide a wrist singularity behind it; snapping moves the TCP by at most this
#: times the arm's size.
STRETCH_TOL = 1e-13

#: Two solutions closer than this (max abs difference of wrapped joint
#: values, rad or length units) are one solution.
SAME_SOLUTION_TOL = 1e-9

#: Every solution the single-pose IK returns is put back through FK; a
#: position error above this (times the arm's size) or a rotation error above
#: it means a bug in rikin, and raises instead of returning a wrong answer.
FK_CHECK_TOL = 1e-8

#: Angles are read modulo 2*pi; one above this (rad, one turn) in absolute value
#: is checked for being degrees typed by mistake (see ``_validate.check_radians``).
DEGREES_SUSPECT = 2 * 3.141592653589793 + 1e-9

#: A value beyond one turn that is a whole multiple of 5 between these bounds
#: (10 ... 720) is a round number of degrees, not radians.
DEGREES_ROUND = (10.0, 720.0)

#: Two or more joint values of one configuration beyond this (four turns, rad)
#: are degrees: unwrapped radian solutions stay within a turn or two.
DEGREES_FAR = 8 * 3.141592653589793

#: An angle beyond this (rad) has lost its fractional turn to rounding
#: (spacing of doubles there ~1e-10 rad): refused as meaningless.
MAX_ANGLE = 1e6

#: An angle of a DH table (twist, revolute offset, prismatic theta) this far or less (rad)
#: from a multiple of 90 deg was most likely a right angle typed rounded: 1.571 for pi/2
#: or 3.142 for pi (3 decimals leave up to 5e-4 rad, 3.14 leaves 1.6e-3). A lean of
#: 0.3 deg (5.2e-3 rad) is a lean. The families name such angles when an arm is in none
#: (``rikin.ik.families``); the typed-table reader refuses such a number under a header in
#: degrees (``rikin.dhtext``: read as degrees it would be another arm).
ROUNDED_RIGHT_ANGLE = 2e-3
