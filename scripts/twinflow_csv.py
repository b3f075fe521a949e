"""Reader of twinflow monitor CSVs (comment lines start with '#', then a header row)."""


def read(path):
    """Returns (header names as written, rows as lists of floats)."""
    header, rows = None, []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            if header is None:
                header = line.split(",")
                continue
            rows.append([float(v) for v in line.split(",")])
    return header, rows
