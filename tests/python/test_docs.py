# SPDX-License-Identifier: MIT
"""Every public name of the package has a docstring of its own (beyond pybind11's
signature line), and docs/PYTHON.md mentions every public function and class."""
import inspect
import re

import graphslam
from conftest import SOURCE_DIR


def own_doc(obj):
    doc = inspect.getdoc(obj) or ""
    # pybind11 puts "name(signature) -> type" first; what follows is ours.
    lines = [line for line in doc.splitlines() if line.strip() and not re.match(r"^\w+\(.*\)( -> .*)?$", line)]
    return "\n".join(lines)


def public_members(module):
    for name in getattr(module, "__all__", dir(module)):
        if not name.startswith("_"):
            yield name, getattr(module, name)


def test_every_public_name_has_a_docstring():
    missing = []
    for modname, module in (("graphslam", graphslam), ("graphslam.eval", graphslam.eval),
                            ("graphslam.drivebot", graphslam.drivebot)):
        for name, obj in public_members(module):
            if inspect.ismodule(obj) or name == "__version__":
                continue
            if not own_doc(obj):
                missing.append(f"{modname}.{name}")
            if inspect.isclass(obj) and not issubclass(obj, BaseException):
                for attr, member in vars(obj).items():
                    if attr.startswith("_") and attr not in ("__init__", "__getitem__"):
                        continue
                    if not (callable(member) or isinstance(member, property)
                            or type(member).__name__ == "property"):
                        continue  # plain class attributes (CustomEdge.tag) are documented by the class
                    if not own_doc(member):
                        missing.append(f"{modname}.{name}.{attr}")
    assert not missing, missing


def test_docs_mention_the_api():
    text = (SOURCE_DIR / "docs" / "PYTHON.md").read_text()
    absent = [name for name, obj in public_members(graphslam)
              if not inspect.ismodule(obj) and not name.startswith("__") and name not in text]
    assert not absent, absent
