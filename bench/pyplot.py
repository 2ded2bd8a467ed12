"""matplotlib's pyplot for the bench scripts' PNGs, drawing to files only (the Agg backend), or None
where matplotlib is not installed: the CSVs hold every number, so a missing plot is no failure.

    from pyplot import pyplot_or_none
    plt = pyplot_or_none()
    if plt is None:
        return
"""


def pyplot_or_none():
    try:
        import matplotlib
    except ImportError:
        print("no plot: python3-matplotlib is not installed (the CSV has every number)")
        return None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt
