"""A page's link to a path outside docs/ (../tools/setup, ../ensembles/presets/x.toml) is an error.

The site holds docs/ alone, so such a link would lead nowhere (a folder) or to a stray copy (a
file). The warning names the page, its line and the path; write the path as code instead.
"""
import posixpath

from docutils import nodes
from sphinx import addnodes
from sphinx.util import logging

logger = logging.getLogger(__name__)


def check_links(app, doctree):
    folder = posixpath.dirname(app.env.docname)
    for link in list(doctree.findall(
            lambda n: isinstance(n, (addnodes.pending_xref, addnodes.download_reference))
            and n.get("reftype") == "myst")):
        path = link["reftarget"].split("#", 1)[0]
        where = posixpath.normpath(posixpath.join(folder, path)) if path else ""
        if where != ".." and not where.startswith("../"):
            continue
        logger.warning(f"link to '{path}' leaves docs/, and the site holds docs/ alone: write "
                       f"the path as code, `{where[3:] or '.'}`, instead of linking it",
                       location=link, type="qmaps", subtype="outside_docs")
        link.replace_self(nodes.inline("", "", *link.children))


def setup(app):
    # Before Sphinx's collectors (priority 500) turn a link to a file into a download.
    app.connect("doctree-read", check_links, priority=400)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
