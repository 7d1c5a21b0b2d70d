"""Preprocessing of press videos: contact-frame selection (paper Sec. II-A)."""

from ._contact import ContactFrameSelector, ContactNotFoundWarning
from ._contact_curve import contact_curve
from ._plotting import plot_contact_selection

__all__ = ["ContactFrameSelector", "ContactNotFoundWarning", "contact_curve", "plot_contact_selection"]
