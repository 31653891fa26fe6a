"""Issue 35 item 6: the documentation a user can navigate. The README keeps what a
newcomer needs (what rotorjax is, the two set-up commands, the first ten minutes, the
map of capabilities linking each page); the rest is the documentation site, built from
the repository by mkdocs (the README as its home page, the API reference generated
from the docstrings, the notebooks rendered with their outputs, the benchmark page),
here with warnings as errors. Every command and Python block of its pages runs in
tests/test_readme.py, as the README's do."""

import os
import re
import subprocess
import sys

import pytest
import yaml

from .helpers import DOCS_PAGES, documentation

ROOT = os.path.join(os.path.dirname(__file__), "..")


def _nav_pages(nav):
    for item in nav:
        value = next(iter(item.values())) if isinstance(item, dict) else item
        if isinstance(value, list):
            yield from _nav_pages(value)
        else:
            yield value


class _Loader(yaml.SafeLoader):
    """mkdocs.yml's tags (none used today) read as plain values."""


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("site")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)], cwd=ROOT,
                         capture_output=True, text=True, env=env, timeout=900)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert "WARNING" not in run.stderr, run.stderr[-3000:]
    return out


def test_the_site_builds_with_warnings_as_errors_and_holds_every_page(site):
    with open(os.path.join(ROOT, "mkdocs.yml")) as f:
        config = yaml.load(f, Loader=_Loader)
    pages = list(_nav_pages(config["nav"]))
    # every documentation page is in the site's navigation, and the tests read every page it has
    assert sorted(f"docs/{p}" for p in pages if p.endswith(".md") and p not in ("index.md", "api.md",
                                                                                 "benchmarks/README.md")) \
        == sorted(p for p in DOCS_PAGES if p != "README.md")
    for page in pages:
        stem = re.sub(r"(index|README)?\.(md|ipynb)$", "", page).rstrip("/")
        html = os.path.join(site, stem, "index.html") if stem else os.path.join(site, "index.html")
        assert os.path.getsize(html) > 5000, page
    home = open(os.path.join(site, "index.html"), encoding="utf-8").read()
    assert "The first ten minutes" in home and 'href="rotor-files/"' in home   # the README, its links rewritten


def test_the_api_reference_is_the_docstrings_of_every_exported_name(site):
    import rotorjax.analysis
    import rotorjax.models

    api = open(os.path.join(site, "api", "index.html"), encoding="utf-8").read()
    for package, name in ((rotorjax.analysis, "modes"), (rotorjax.analysis, "campbell"),
                          (rotorjax.models, "RotorScene"), (rotorjax.analysis, "api684_margins")):
        assert f'id="{package.__name__}.{name}"' in api, name
        first = " ".join(getattr(package, name).__doc__.split())[:40]
        assert first.split("`")[0] in re.sub(r"<[^>]+>", "", " ".join(api.split())), name


def test_the_notebooks_are_rendered_with_their_figures(site):
    for name in ("everyday", "parameter_study", "identification", "stability_boundaries", "fluid_films",
                 "periodic", "design_uncertainty"):
        page = open(os.path.join(site, "notebooks", name, "index.html"), encoding="utf-8").read()
        assert "data:image/png;base64," in page, name   # the committed outputs, figures inline


def test_the_readme_is_a_newcomers_page():
    readme = documentation("README.md")
    assert len(readme.splitlines()) < 150
    setup = re.findall(r"```bash\n(.*?)```", readme, flags=re.S)[:2]
    assert setup == ['python3 -m pip install . && rotorjax demo\n',
                     'python3 -m pip install -e ".[test]" && python3 -m pytest -q\n']
    assert "## The first ten minutes" in readme
    for page in DOCS_PAGES[1:]:
        assert f"]({page})" in readme, page   # the map of capabilities links every page
