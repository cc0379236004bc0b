"""``Model.plot``: a section view drawn with matplotlib, with a legend."""


def plot(model, ax=None, **slice_args):
    """Draw ``model.slice(**slice_args)`` (without its legend strip) on
    ``ax`` (a new figure's when None), in model units, with a legend of the
    regions, overlaps and void in it. Returns the Axes."""
    import matplotlib.patches as mpatches
    import matplotlib.pyplot as plt

    slice_args["legend"] = False
    section = model.slice(**slice_args)
    if ax is None:
        _, ax = plt.subplots()
    width, height = section.extent
    right, up = section.axes
    # Coordinates along the plane's axes, so that a z= section shows x and y.
    centre_u = sum(c * a for c, a in zip(section.centre, right))
    centre_v = sum(c * a for c, a in zip(section.centre, up))
    ax.imshow(
        section.rgb,
        extent=(
            centre_u - width / 2,
            centre_u + width / 2,
            centre_v - height / 2,
            centre_v + height / 2,
        ),
        interpolation="nearest",
    )
    ax.set_xlabel(f"{_axis_name(right)} ({model.unit})")
    ax.set_ylabel(f"{_axis_name(up)} ({model.unit})")
    entries = list(section.legend) + list(section.overlaps)
    if section.void is not None:
        entries.append(section.void)
    handles = [mpatches.Patch(color=e["colour"], label=e["label"]) for e in entries]
    if handles:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    return ax


def _axis_name(direction):
    """"x", "y", "z" for a coordinate axis, else the direction."""
    for name, axis in zip("xyz", ((1, 0, 0), (0, 1, 0), (0, 0, 1))):
        if tuple(direction) == axis:
            return name
    return "along " + str(tuple(round(c, 6) for c in direction))
