"""List the public entities of the library that have no FORD documentation.

usage: .venv/bin/python tools/doc_coverage.py ford.md

Reads the sources the FORD project file names with FORD's own parser and reports,
one line each, every public module entity without a `!>` comment: modules, public
procedures and their dummy arguments, public derived types, their public components
and type-bound procedures (the binding or its procedure; for a binding that a type
introduces, not overrides, also that procedure's dummy arguments, which the parent's
interface documents otherwise), public variables and named constants, abstract
interfaces and their dummy arguments, and procedures outside modules with their
arguments. Exits with status 1 when anything is missing. FORD's own `warn` setting cannot tell these apart from the
private entities and local variables it also lists.
"""
import contextlib
import io
import sys
from pathlib import Path

from ford.fortran_project import Project
from ford.settings import load_markdown_settings
from ford.sourceform import FortranProcedure, FortranSourceFile


def documented(entity):
    return any(line.strip() for line in getattr(entity, "doc_list", []) or [])


def where(entity):
    return Path(getattr(entity, "filename", "?")).name


def check_procedure(proc, label, missing, need_doc=True):
    """A procedure and its dummy arguments."""
    if need_doc and not documented(proc):
        missing.append(f"{where(proc)}: {label} has no comment")
    for arg in getattr(proc, "args", []) or []:
        if isinstance(arg, str):
            continue
        if not documented(arg):
            missing.append(f"{where(proc)}: argument '{arg.name}' of {label} has no comment")


def is_public(entity):
    return getattr(entity, "permission", "public") in ("public", "protected")


def overrides(dtype, name):
    """Whether a type's ancestors already have a binding of this name."""
    parent = getattr(dtype, "extends", None)
    while parent is not None and not isinstance(parent, str):
        if any(b.name.lower() == name.lower() for b in getattr(parent, "boundprocs", [])):
            return True
        parent = getattr(parent, "extends", None)
    return False


def check_module(module, missing):
    if not documented(module):
        missing.append(f"{where(module)}: module {module.name} has no comment")
    local = lambda entity: getattr(entity, "parent", None) is module  # noqa: E731
    for proc in list(module.subroutines) + list(module.functions):
        if is_public(proc):
            check_procedure(proc, f"{module.name}::{proc.name}", missing)
    for interface in module.interfaces:
        if is_public(interface) and not documented(interface):
            missing.append(f"{where(module)}: interface {module.name}::{interface.name} has no comment")
    for interface in module.absinterfaces:
        if is_public(interface):
            # FORD keeps the comment and the arguments on the procedure inside
            check_procedure(getattr(interface, "procedure", interface), f"{module.name}::{interface.name}", missing)
    for variable in module.variables:
        if is_public(variable) and local(variable) and not documented(variable):
            missing.append(f"{where(module)}: {module.name}::{variable.name} has no comment")
    for dtype in module.types:
        if not is_public(dtype):
            continue
        label = f"{module.name}::{dtype.name}"
        if not documented(dtype):
            missing.append(f"{where(module)}: type {label} has no comment")
        for component in getattr(dtype, "local_variables", dtype.variables):
            if is_public(component) and not documented(component):
                missing.append(f"{where(module)}: component {label}%{component.name} has no comment")
        for binding in dtype.boundprocs:
            if not is_public(binding) or getattr(binding, "parent", dtype) is not dtype:
                continue
            targets = [b for b in getattr(binding, "bindings", []) if isinstance(b, FortranProcedure)]
            if not documented(binding) and not any(documented(t) for t in targets):
                missing.append(f"{where(module)}: binding {label}%{binding.name} has no comment")
            if overrides(dtype, binding.name):
                continue
            for target in targets:
                if getattr(target, "parent", None) is module:
                    check_procedure(target, f"{module.name}::{target.name} (bound to {label}%{binding.name})",
                                    missing, need_doc=False)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    project_file = Path(sys.argv[1])
    settings, _ = load_markdown_settings(project_file.parent, project_file.read_text(), str(project_file))
    settings.normalise_paths(project_file.parent.resolve())
    settings.warn = False
    settings.quiet = True
    with contextlib.redirect_stdout(io.StringIO()):  # FORD's progress bar
        project = Project(settings)
        project.correlate()
    missing = []
    for module in project.modules:
        check_module(module, missing)
    for proc in project.procedures:
        if isinstance(getattr(proc, "parent", None), FortranSourceFile):
            check_procedure(proc, proc.name, missing)
    for line in sorted(set(missing)):
        print("undocumented:", line)
    if missing:
        print(f"{len(set(missing))} public entities without documentation", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
