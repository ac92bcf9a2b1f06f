"""Each Jupyter notebook (.ipynb) under docs/ as a page, with the outputs it has stored.

The notebook becomes MyST text, which MyST then parses as any page: markdown cells as they are,
code cells as code blocks in the notebook's language, text outputs (streams, results, errors) as
literal blocks, and PNG outputs as images, written under the build's doctree folder so that the
source tree stays as it is.
"""
import base64
import json
import os
import re

from myst_parser.parsers.sphinx_ import MystParser

ANSI_ESCAPE = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")


def text_of(value):
    """A notebook's text field: a string, or a list of lines."""
    return "".join(value) if isinstance(value, list) else value


def fenced(info, text):
    """`text` in a code fence, longer than any run of backticks inside it."""
    longest = max((len(run) for run in re.findall(r"`+", text)), default=0)
    fence = "`" * max(3, longest + 1)
    return f"{fence}{info}\n{text.rstrip()}\n{fence}"


class NotebookParser(MystParser):
    """Parses a notebook's JSON as the MyST page that shows its cells and outputs."""

    supported = ("jupyter_notebook",)

    def parse(self, inputstring, document):
        env = document.settings.env
        notebook = json.loads(inputstring)
        language = notebook.get("metadata", {}).get("language_info", {}).get("name", "python")
        blocks = []
        for number, cell in enumerate(notebook["cells"]):
            source = text_of(cell.get("source", ""))
            if cell["cell_type"] == "markdown":
                blocks.append(source)
            elif cell["cell_type"] == "code":
                blocks.append(fenced(language, source))
                for k, output in enumerate(cell.get("outputs", [])):
                    name = f"{os.path.basename(env.docname)}-cell{number}-{k}"
                    blocks += self.output_blocks(env, name, output)
        super().parse("\n\n".join(blocks) + "\n", document)

    @staticmethod
    def output_blocks(env, name, output):
        """The MyST blocks of one output: an image for a PNG, else a literal block of its text."""
        kind = output["output_type"]
        if kind == "stream":
            return [fenced("text", text_of(output["text"]))]
        if kind == "error":
            return [fenced("text", ANSI_ESCAPE.sub("", "\n".join(output["traceback"])))]
        data = output.get("data", {})
        if "image/png" in data:
            folder = os.path.join(env.doctreedir, "notebook-outputs", env.docname)
            os.makedirs(folder, exist_ok=True)
            image = os.path.join(folder, name + ".png")
            with open(image, "wb") as f:
                f.write(base64.b64decode(text_of(data["image/png"])))
            # A path that starts with / is taken from the source folder.
            return [f"```{{image}} /{os.path.relpath(image, env.srcdir)}\n:alt: {name}\n```"]
        if "text/plain" in data:
            return [fenced("text", text_of(data["text/plain"]))]
        return []


def setup(app):
    app.add_source_suffix(".ipynb", "jupyter_notebook")
    app.add_source_parser(NotebookParser)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
