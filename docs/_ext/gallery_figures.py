"""sphinx-gallery hooks for the figure scripts in examples/ (named in conf.py by their fully
qualified names, so the configuration stays picklable and Sphinx can cache it).

The figure scripts write their figure to a file and close it, so matplotlib's scraper sees
nothing: the gallery runs them with ``--out FIGURE_OUT`` (never into the source tree), and
`scrape_written_figures` moves what they wrote into the gallery."""
import shutil
import tempfile
from pathlib import Path

#: where the figure scripts write during the build
FIGURE_OUT = Path(tempfile.mkdtemp(prefix="fputlab-gallery-"))


def figure_script_argv(gallery_conf, script_vars):
    """Command line of an example run by the gallery: figure scripts get ``--out FIGURE_OUT``."""
    name = Path(script_vars["src_file"]).name
    if name == "thermalization_teq.py":     # --out is its file name, not a directory
        return ["--out", str(FIGURE_OUT / "thermalization_teq.png")]
    return ["--out", str(FIGURE_OUT)] if name.startswith("fig") else []


def scrape_written_figures(block, block_vars, gallery_conf):
    """Every image written to FIGURE_OUT since the last call, moved into the gallery, then any
    matplotlib figure still open (matplotlib's own scraper)."""
    from sphinx_gallery.scrapers import figure_rst, matplotlib_scraper
    paths = []
    for written in sorted(FIGURE_OUT.glob("*.png")):
        dest = next(block_vars["image_path_iterator"])
        shutil.move(written, dest)
        paths.append(dest)
    rst = figure_rst(paths, gallery_conf["src_dir"]) if paths else ""
    return rst + matplotlib_scraper(block, block_vars, gallery_conf)
