"""The framed 3-D rod: per-bar material frames as quaternions (:mod:`~guidewire.rod.quaternion`), bending and twist
at the joints (:mod:`~guidewire.rod.strain`, :mod:`~guidewire.rod.strain_energy`) with exact derivatives through
second-order jets (:mod:`~guidewire.rod.jet`), the chain's nodes (:mod:`~guidewire.rod.kinematics`) and the twist
material (:mod:`~guidewire.rod.material`)."""
