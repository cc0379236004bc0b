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
    ax.imshow(
        section.rgb,
        extent=(-width / 2, width / 2, -height / 2, height / 2),
        interpolation="nearest",
    )
    ax.set_xlabel(f"along {tuple(round(c, 6) for c in section.axes[0])} ({model.unit})")
    ax.set_ylabel(f"along {tuple(round(c, 6) for c in section.axes[1])} ({model.unit})")
    entries = list(section.legend) + list(section.overlaps)
    if section.void is not None:
        entries.append(section.void)
    handles = [mpatches.Patch(color=e["colour"], label=e["label"]) for e in entries]
    if handles:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    return ax
