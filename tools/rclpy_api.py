"""Writes the public names of one release of rclpy as JSON, read from its source with `ast` (nothing is imported or
built), for test/unit/test_rclpy_humble_api.py, which checks that the ROS 2 code uses only names that release has:
    python3 tools/rclpy_api.py GIT_DIR REF > test/data/rclpy_humble_api.json
GIT_DIR: a clone of https://github.com/ros2/rclpy (its .git folder, or a bare one); REF: the branch or tag to read
(humble: Humble's rclpy 3.3). The file records the commit and this command.

What it records, for every module of rclpy/rclpy/ (the Python package; its C extension _rclpy is left out):
- "modules": each module's public names (defined, assigned or imported at its top level), each mapped to what it
  names: a module, class or function by its full name, "instance:<class>" for a value made by calling an rclpy class,
  or null for any other value;
- "classes": each class's bases (full names, or the name as written when outside rclpy), its public members (methods,
  properties, class attributes, and `self.<name>` assigned in its methods), mapped as above (a property to what its
  return annotation names), and whether a base outside rclpy may add members the source does not show ("open");
- "functions": each function's and method's keyword parameters, whether it takes **kwargs, and the rclpy class its
  return annotation names, if any.
Names starting with an underscore are not public and are left out (but __init__'s parameters, as the class's).
"""
import ast
import json
import posixpath
import subprocess
import sys

PACKAGE_DIR = "rclpy/rclpy"
# Bases outside rclpy whose public members are known: what `enum` and `Exception` give every subclass. A class with
# any other outside base is "open".
KNOWN_BASES = {"object": [], "Enum": ["name", "value"], "IntEnum": ["name", "value"], "IntFlag": ["name", "value"],
               "Exception": ["args", "with_traceback"], "RuntimeError": ["args", "with_traceback"],
               "ValueError": ["args", "with_traceback"], "TypeError": ["args", "with_traceback"]}


def git(git_dir, *arguments):
    return subprocess.run(["git", "--git-dir", git_dir] + list(arguments), check=True, stdout=subprocess.PIPE,
                          universal_newlines=True).stdout


def module_sources(git_dir, ref):
    """{module name: source} of every .py file of the package at `ref`."""
    sources = {}
    for path in git(git_dir, "ls-tree", "-r", "--name-only", ref, PACKAGE_DIR).split():
        if path.endswith(".py"):
            parts = posixpath.splitext(posixpath.relpath(path, posixpath.dirname(PACKAGE_DIR)))[0].split("/")
            if parts[-1] == "__init__":
                parts.pop()
            sources[".".join(parts)] = git(git_dir, "show", "%s:%s" % (ref, path))
    return sources


def public(name):
    return not name.startswith("_")


def top_level(statements):
    """The statements of a module's or class's body, those inside `if`, `try` and `with` blocks included."""
    for statement in statements:
        if isinstance(statement, (ast.If, ast.Try, ast.With)):
            yield from top_level(statement.body)
            yield from top_level(getattr(statement, "orelse", []))
            for handler in getattr(statement, "handlers", []):
                yield from top_level(handler.body)
            yield from top_level(getattr(statement, "finalbody", []))
        else:
            yield statement


def dotted(expression):
    """'a.b.c' for a chain of names, else None."""
    if isinstance(expression, ast.Name):
        return expression.id
    if isinstance(expression, ast.Attribute):
        prefix = dotted(expression.value)
        return prefix and prefix + "." + expression.attr
    if isinstance(expression, ast.Constant) and isinstance(expression.value, str):  # a forward reference
        return expression.value
    return None


def assigned_names(statement):
    targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
    return [target.id for target in targets if isinstance(target, ast.Name)]


class Reader:
    """Reads every module; names are resolved once all are read (a module may import from any other)."""

    def __init__(self, sources):
        self.sources = sources
        self.scopes = {}  # module -> {name: reference}: "ref:<dotted name>", "instance-of:<dotted>", None, or a def
        self.classes = {}
        self.functions = {}

    def read(self):
        for module, source in sorted(self.sources.items()):
            self.scopes[module] = self.read_scope(module, ast.parse(source, module).body)

    def read_scope(self, module, body):
        scope = {}
        for statement in top_level(body):
            if isinstance(statement, (ast.Import, ast.ImportFrom)):
                scope.update(self.imported(module, statement))
            elif isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                full_name = "%s.%s" % (module, statement.name)
                scope[statement.name] = "def:" + full_name
                table = self.classes if isinstance(statement, ast.ClassDef) else self.functions
                table[full_name] = (module, statement)
            elif isinstance(statement, (ast.Assign, ast.AnnAssign)):
                made_by = statement.value if isinstance(statement.value, ast.Call) else None
                for name in assigned_names(statement):
                    scope[name] = "instance-of:" + dotted(made_by.func) if made_by and dotted(made_by.func) else None
        return scope

    def imported(self, module, statement):
        """{name: reference} of what an import binds."""
        if isinstance(statement, ast.Import):
            # `import a.b` binds a; `import a.b as c` binds c to a.b.
            bound = [(alias.asname, alias.name) if alias.asname else (alias.name.split(".")[0],) * 2
                     for alias in statement.names]
            return {name: "ref:" + target for name, target in bound}
        source = self.absolute(module, statement)
        return {alias.asname or alias.name: "ref:%s.%s" % (source, alias.name)
                for alias in statement.names if alias.name != "*"}

    def absolute(self, module, statement):
        if not statement.level:
            return statement.module
        package = module if module in self.sources and self.is_package(module) else module.rsplit(".", 1)[0]
        for _ in range(statement.level - 1):
            package = package.rsplit(".", 1)[0]
        return package + ("." + statement.module if statement.module else "")

    def is_package(self, module):
        return any(other.startswith(module + ".") for other in self.sources)

    def resolve(self, module, name, depth=0):
        """The full name of what `name` names in `module` ("a.b" resolved step by step), or None."""
        head, _, rest = name.partition(".")
        reference = self.scopes.get(module, {}).get(head, "ref:" + head if head == "rclpy" else None)
        target = self.follow(reference, depth)
        for part in rest.split(".") if rest else []:
            target = self.member(target, part, depth)
        return target

    def follow(self, reference, depth):
        if not reference or depth > 20 or reference.startswith("instance-of:"):
            return None
        full_name = reference.split(":", 1)[1]
        if reference.startswith("def:") or full_name in self.sources:
            return full_name
        module, _, name = full_name.rpartition(".")
        if module in self.sources:
            return self.resolve(module, name, depth + 1)
        return None

    def member(self, target, name, depth):
        if target in self.sources:
            if target + "." + name in self.sources:
                return target + "." + name
            return self.resolve(target, name, depth + 1)
        return None

    def value(self, module, reference):
        """What a name of a scope stands for in the output."""
        if reference and reference.startswith("instance-of:"):
            made_by = self.resolve(module, reference.split(":", 1)[1])
            return "instance:" + made_by if made_by in self.classes else None
        if reference is None:
            return None
        full_name = reference.split(":", 1)[1]
        # An outside name (os, typing) is not one of rclpy's: kept as a value of unknown kind.
        return self.follow(reference, 0) if full_name.split(".")[0] == "rclpy" else None


def parameters(function, method):
    arguments = function.args
    positional = [argument.arg for argument in arguments.args]
    if method and positional and not any(isinstance(d, ast.Name) and d.id == "staticmethod"
                                         for d in function.decorator_list):
        positional = positional[1:]
    return positional + [argument.arg for argument in arguments.kwonlyargs], arguments.kwarg is not None


def is_property(function):
    return any(dotted(decorator) in ("property", "abc.abstractproperty") for decorator in function.decorator_list)


def describe_function(reader, module, function, method):
    names, any_keyword = parameters(function, method)
    returns = reader.resolve(module, dotted(function.returns)) if dotted(function.returns) else None
    return {"parameters": names, "any_keyword": any_keyword,
            "returns": returns if returns in reader.classes else None}


def self_attributes(class_def):
    """The public names assigned as `self.<name>` in the class's methods."""
    names = set()
    for node in ast.walk(class_def):
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
        for target in targets if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)) else []:
            if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self":
                names.add(target.attr)
    return {name for name in names if public(name)}


def describe_class(reader, full_name, module, class_def, functions):
    bases, open_class = [], False
    for base in class_def.bases:
        written = dotted(base) or "?"
        resolved = reader.resolve(module, written)
        if resolved in reader.classes:
            bases.append(resolved)
        else:
            bases.append(written)
            open_class = open_class or written.split(".")[-1] not in KNOWN_BASES
    members = {name: None for name in self_attributes(class_def)}
    members.update({name: None for base in class_def.bases
                    for name in KNOWN_BASES.get((dotted(base) or "").split(".")[-1], [])})
    for statement in top_level(class_def.body):
        if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef)):
            if public(statement.name) or statement.name == "__init__":
                method = describe_function(reader, module, statement, True)
                if is_property(statement):
                    members[statement.name] = "instance:" + method["returns"] if method["returns"] else None
                else:
                    functions[full_name + "." + statement.name] = method
                    members[statement.name] = full_name + "." + statement.name
        elif isinstance(statement, (ast.Assign, ast.AnnAssign)):
            members.update({name: None for name in assigned_names(statement) if public(name)})
        elif isinstance(statement, ast.ClassDef) and public(statement.name):
            members[statement.name] = None
    return {"bases": bases, "open": open_class, "members": dict(sorted(members.items()))}


def api(sources):
    reader = Reader(sources)
    reader.read()
    modules = {module: {"names": {name: reader.value(module, reference)
                                  for name, reference in sorted(scope.items()) if public(name)}}
               for module, scope in sorted(reader.scopes.items())}
    functions = {full_name: describe_function(reader, module, function, False)
                 for full_name, (module, function) in reader.functions.items()}
    classes = {full_name: describe_class(reader, full_name, module, class_def, functions)
               for full_name, (module, class_def) in sorted(reader.classes.items())}
    return {"modules": modules, "classes": classes, "functions": dict(sorted(functions.items()))}


def main(argv):
    if len(argv) != 3:
        sys.stderr.write("usage: python3 tools/rclpy_api.py GIT_DIR REF > FILE.json\n")
        return 2
    git_dir, ref = argv[1], argv[2]
    commit = git(git_dir, "rev-parse", ref + "^{commit}").strip()
    version = [line.strip() for line in git(git_dir, "show", ref + ":rclpy/package.xml").splitlines()
               if line.strip().startswith("<version>")][0][len("<version>"):-len("</version>")]
    document = {"source": {"repository": "https://github.com/ros2/rclpy", "ref": ref, "commit": commit,
                           "version": version},
                "generated_by": "python3 tools/rclpy_api.py GIT_DIR %s > test/data/rclpy_%s_api.json"
                                % (ref, ref)}
    document.update(api(module_sources(git_dir, commit)))
    json.dump(document, sys.stdout, indent=1, sort_keys=False)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
