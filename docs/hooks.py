"""mkdocs hooks.

- The home page is the README: docs/index.md holds only a marker, replaced here by the
  README's text, whose links point into docs/ from the repository's root (and, on the
  site, from docs/).
- The API reference (docs/api.md, a marker per package) lists each package's public
  names as the package exports them (`rotorjax.analysis.modes`, not the private module
  that defines it), one entry per name from its docstring (mkdocstrings)."""

import os
import re

README = "<!-- the README -->"
API = re.compile(r"<!-- the API of (\S+) -->")


def _api(package):
    """mkdocstrings entries for `package`'s public functions and classes."""
    import importlib
    import inspect

    module = importlib.import_module(package)
    names = [n for n in dir(module) if not n.startswith("_")]
    entries = []
    for name in names:
        obj = getattr(module, name)
        if (inspect.isfunction(obj) or inspect.isclass(obj)) and obj.__module__.startswith("rotorjax"):
            entries.append(f"### `{package}.{name}`\n\n::: {package}.{name}\n    options:\n"
                           "      show_root_heading: false\n      heading_level: 4\n")
    return "\n".join(entries)


def on_page_markdown(markdown, page, config, **kwargs):
    if README in markdown:
        readme = os.path.join(os.path.dirname(config["config_file_path"]), "README.md")
        with open(readme, encoding="utf-8") as f:
            text = f.read()
        text = text.replace("](docs/", "](").replace("](notebooks/)", "](notebooks/parameter_study.ipynb)")
        markdown = markdown.replace(README, text)
    return API.sub(lambda m: _api(m.group(1)), markdown)
