"""The ROS 2 code runs on Humble, checked without Humble: every public rclpy name it uses must be one that Humble's
rclpy 3.3 has. test/data/rclpy_humble_api.json lists those names (read from Humble's source by tools/rclpy_api.py;
the file records the commit and the command). The ROS 2 modules, programs and tests are read with `ast`, and a
failure names the file, the line and the name Humble lacks.

What is checked: `import rclpy.x` and `from rclpy.x import Y`; attribute chains on rclpy modules, classes and on
values whose rclpy class is known here (made by calling an rclpy class, returned by an rclpy call whose return
annotation names its class, a parameter annotated with it, or `self` in a subclass of an rclpy class, for the
names the subclass does not define itself); keyword arguments of calls to rclpy functions, methods and classes.
Not checked: names starting with an underscore, values whose class is not known this way (a variable assigned
from different sources, the members of what rclpy's C extension defines, such as SignalHandlerOptions), and
positional arguments."""
import ast
import json
import pathlib

import pytest

REPO_DIR = pathlib.Path(__file__).resolve().parents[2]
API_FILE = REPO_DIR / "test" / "data" / "rclpy_humble_api.json"
CHECKED = [REPO_DIR / "src" / "cssr_system" / "ros2", REPO_DIR / "ros2" / "cssr_system" / "scripts",
           REPO_DIR / "test" / "ros2"]


def checked_files():
    files = []
    for place in CHECKED:
        files += sorted(path for path in place.rglob("*") if path.is_file() and is_python(path))
    return files


def is_python(path):
    if path.suffix == ".py":
        return True
    with open(str(path), "rb") as source:
        first_line = source.readline()
    return first_line.startswith(b"#!") and b"python" in first_line


class Api:
    """Humble's rclpy as the data file lists it. A type is ("module" | "class" | "function" | "instance", full
    name), or ("subclass", rclpy base, names the subclass defines), or None when not known."""

    def __init__(self, document):
        self.modules = document["modules"]
        self.classes = document["classes"]
        self.functions = document["functions"]

    def of_target(self, target):
        if target is None:
            return None
        if target.startswith("instance:"):
            return ("instance", target.split(":", 1)[1])
        for kind, table in (("module", self.modules), ("class", self.classes), ("function", self.functions)):
            if target in table:
                return (kind, target)
        return None

    def class_members(self, name):
        """(members along the bases, whether a base outside rclpy may add more)."""
        members, open_class = {}, False
        for class_name in self.ancestry(name):
            described = self.classes[class_name]
            for member, target in described["members"].items():
                members.setdefault(member, target)
            open_class = open_class or described["open"]
        return members, open_class

    def ancestry(self, name):
        order, pending = [], [name]
        while pending:
            current = pending.pop(0)
            if current in self.classes and current not in order:
                order.append(current)
                pending += self.classes[current]["bases"]
        return order

    def attribute(self, owner, name):
        """(type of owner.name, or None; True when Humble lacks the name)."""
        if owner is None or name.startswith("_"):
            return None, False
        kind, full_name = owner[0], owner[1]
        if kind == "module":
            if full_name + "." + name in self.modules:
                return ("module", full_name + "." + name), False
            names = self.modules[full_name]["names"]
            return (self.of_target(names[name]), False) if name in names else (None, True)
        if kind in ("class", "instance", "subclass"):
            if kind == "subclass" and name in owner[2]:
                return None, False
            members, open_class = self.class_members(full_name)
            if name in members:
                return self.of_target(members[name]), False
            return None, not open_class
        return None, False

    def signature(self, callee):
        """(the function's description, the name to report) of what a call of `callee` runs, or (None, None)."""
        if callee is None:
            return None, None
        if callee[0] == "function":
            return self.functions[callee[1]], callee[1] + "()"
        if callee[0] == "class":
            for class_name in self.ancestry(callee[1]):
                if class_name + ".__init__" in self.functions:
                    return self.functions[class_name + ".__init__"], callee[1] + "()"
        return None, None

    def result(self, callee):
        if callee is not None and callee[0] == "class":
            return ("instance", callee[1])
        if callee is not None and callee[0] == "function":
            return self.of_target(self.functions[callee[1]]["returns"])
        return None


class Checker(ast.NodeVisitor):
    """Walks one module twice: the first pass learns the types of `self.<name>` attributes, the second reports."""

    def __init__(self, api, filename):
        self.api = api
        self.filename = filename
        self.scopes = [{}]
        self.classes = []  # (self's type, {attribute: type}) of the classes being walked
        self.attributes = {}  # class name -> {attribute: type}, from the first pass
        self.problems = set()
        self.reporting = False

    def check(self, tree):
        self.visit(tree)
        self.reporting = True
        self.scopes = [{}]
        self.visit(tree)
        return sorted(self.problems)

    def report(self, node, text):
        if self.reporting:
            self.problems.add((node.lineno, "%s:%d: %s" % (self.filename, node.lineno, text)))

    # Names bound by imports, assignments and parameters.
    def bind(self, name, value):
        self.scopes[-1][name] = value

    def lookup(self, name):
        for scope in reversed(self.scopes):
            if name in scope:
                return scope[name]
        return None

    def visit_Import(self, node):
        for alias in node.names:
            if alias.name.split(".")[0] != "rclpy":
                continue
            if alias.name not in self.api.modules:
                self.report(node, "module %s: Humble's rclpy has no such module" % alias.name)
            bound = alias.name if alias.asname else "rclpy"
            self.bind(alias.asname or "rclpy", ("module", bound) if bound in self.api.modules else None)

    def visit_ImportFrom(self, node):
        if not node.module or node.level or node.module.split(".")[0] != "rclpy":
            return
        if node.module not in self.api.modules:
            self.report(node, "module %s: Humble's rclpy has no such module" % node.module)
            return
        for alias in node.names:
            value, missing = self.api.attribute(("module", node.module), alias.name)
            if missing:
                self.report(node, "%s.%s: Humble's rclpy has no such name" % (node.module, alias.name))
            self.bind(alias.asname or alias.name, value)

    def visit_Assign(self, node):
        value = self.evaluate(node.value)
        for target in node.targets:
            self.assign(target, value)

    def visit_AnnAssign(self, node):
        value = self.evaluate(node.value) if node.value is not None else None
        self.assign(node.target, value or self.evaluate(node.annotation, annotation=True))

    def assign(self, target, value):
        if isinstance(target, ast.Name):
            self.bind(target.id, value)
        elif (isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"
              and self.classes):
            known = self.classes[-1][1]
            # One type for an attribute assigned in several places, or none when they differ.
            known[target.attr] = value if known.get(target.attr, value) == value else None
        else:
            self.evaluate(target)

    def visit_ClassDef(self, node):
        bases = [self.evaluate(base) for base in node.bases]
        for decorator in node.decorator_list:
            self.evaluate(decorator)
        rclpy_base = next((base[1] for base in bases if base and base[0] == "class"), None)
        defined = {item.name for item in node.body if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef))}
        defined |= {name.id for item in node.body for name in ast.walk(item) if isinstance(name, ast.Name)
                    and isinstance(name.ctx, ast.Store) and not isinstance(item, ast.FunctionDef)}
        attributes = self.attributes.setdefault(node.name, {})
        defined |= set(attributes)
        owner = ("subclass", rclpy_base, frozenset(defined)) if rclpy_base else None
        self.bind(node.name, None)
        self.classes.append((owner, attributes))
        self.scopes.append({})
        for item in node.body:
            self.visit(item)
        self.scopes.pop()
        self.classes.pop()

    def visit_FunctionDef(self, node):
        for decorator in node.decorator_list:
            self.evaluate(decorator)
        for default in node.args.defaults + [d for d in node.args.kw_defaults if d is not None]:
            self.evaluate(default)
        scope = {}
        arguments = node.args.posonlyargs + node.args.args + node.args.kwonlyargs
        for index, argument in enumerate(arguments):
            if index == 0 and argument.arg == "self" and self.classes:
                scope["self"] = self.classes[-1][0]
            else:
                scope[argument.arg] = self.evaluate(argument.annotation, annotation=True)
        self.bind(node.name, None)
        self.scopes.append(scope)
        for statement in node.body:
            self.visit(statement)
        self.scopes.pop()

    visit_AsyncFunctionDef = visit_FunctionDef

    def visit_Expr(self, node):
        self.evaluate(node.value)

    def generic_visit(self, node):
        # Statements not handled above: evaluate their expressions, visit their statements.
        for field, value in ast.iter_fields(node):
            for item in value if isinstance(value, list) else [value]:
                if isinstance(item, ast.expr):
                    self.evaluate(item)
                elif isinstance(item, ast.AST):
                    self.visit(item)

    # Expressions.
    def evaluate(self, node, annotation=False):
        """The type of an expression (checking every name and keyword in it), or None."""
        if node is None:
            return None
        if isinstance(node, ast.Name):
            return self.lookup(node.id)
        if isinstance(node, ast.Attribute):
            if isinstance(node.value, ast.Name) and node.value.id == "self" and self.classes:
                if self.classes[-1][1].get(node.attr) is not None:  # assigned in the class's methods
                    return self.classes[-1][1][node.attr]
            owner = self.evaluate(node.value)
            value, missing = self.api.attribute(owner, node.attr)
            if missing:
                self.report(node, "%s.%s: Humble's rclpy has no such name" % (owner[1], node.attr))
            return value
        if isinstance(node, ast.Call):
            return self.call(node)
        if annotation and isinstance(node, ast.Subscript):  # Optional[Node]: the type inside
            self.evaluate(node.value)
            # Python 3.8 wraps a subscript's slice in ast.Index.
            return self.evaluate(node.slice.value if isinstance(node.slice, ast.Index) else node.slice, True)
        self.evaluate_children(node)
        return None

    def evaluate_children(self, node):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.expr):
                self.evaluate(child)
            elif isinstance(child, ast.comprehension):
                self.evaluate(child.iter)
                self.assign(child.target, None)
                for condition in child.ifs:
                    self.evaluate(condition)
            elif isinstance(child, ast.AST):
                self.visit(child)

    def call(self, node):
        callee = self.evaluate(node.func)
        for argument in node.args:
            self.evaluate(argument)
        described, name = self.api.signature(callee)
        for keyword in node.keywords:
            self.evaluate(keyword.value)
            if (described is not None and keyword.arg is not None and not described["any_keyword"]
                    and keyword.arg not in described["parameters"]):
                self.report(node, "%s has no keyword argument '%s' in Humble's rclpy" % (name, keyword.arg))
        return self.api.result(callee)


@pytest.fixture(scope="module")
def api():
    with open(str(API_FILE)) as source:
        return Api(json.load(source))


def problems_in(api, source, filename="<module>"):
    checker = Checker(api, filename)
    return [text for _, text in checker.check(ast.parse(source, filename))]


def test_the_data_file_says_where_it_comes_from(api):
    with open(str(API_FILE)) as source:
        document = json.load(source)
    assert document["source"]["ref"] == "humble"
    assert document["source"]["version"].startswith("3.3.")
    assert len(document["source"]["commit"]) == 40
    assert document["generated_by"].startswith("python3 tools/rclpy_api.py ")
    # What the ROS 2 code leans on: if these were missing, the data would be wrong, not the code.
    assert "create_subscription" in api.classes["rclpy.node.Node"]["members"]
    assert "ActionClient" in api.modules["rclpy.action"]["names"]


def test_the_ros2_code_uses_only_what_humbles_rclpy_has(api):
    files = checked_files()
    assert any(path.name == "animate_behaviour_main.py" for path in files)
    assert any(path.name == "animate_behaviour" for path in files)  # a program without .py
    problems = []
    for path in files:
        problems += problems_in(api, path.read_text(), str(path.relative_to(REPO_DIR)))
    assert problems == [], "names that Humble's rclpy 3.3 lacks:\n" + "\n".join(problems)


LACKING = {
    # Node(enable_logger_service=...): Iron and later.
    "a class's keyword": ("from rclpy.node import Node\nnode = Node('n', enable_logger_service=True)\n",
                          "<module>:2: rclpy.node.Node() has no keyword argument 'enable_logger_service' in "
                          "Humble's rclpy"),
    # rclpy.event_handler: Iron's name of Humble's rclpy.qos_event.
    "a module, imported from": ("from rclpy.event_handler import SubscriptionEventCallbacks\n",
                                "<module>:1: module rclpy.event_handler: Humble's rclpy has no such module"),
    "a module, imported": ("import rclpy.event_handler\n",
                           "<module>:1: module rclpy.event_handler: Humble's rclpy has no such module"),
    "a name of a module": ("from rclpy.qos import QoSProfile, DurabilityPolicy, NoSuchPolicy\n",
                           "<module>:1: rclpy.qos.NoSuchPolicy: Humble's rclpy has no such name"),
    # DurabilityPolicy.BEST_AVAILABLE: Iron and later.
    "an attribute chain": ("import rclpy\nrclpy.qos.DurabilityPolicy.TRANSIENT_LOCAL\n"
                           "rclpy.qos.DurabilityPolicy.BEST_AVAILABLE\n",
                           "<module>:3: rclpy.qos.DurabilityPolicy.BEST_AVAILABLE: Humble's rclpy has no such name"),
    # An annotated parameter, what a method's return annotation names, a method's keyword (create_timer's
    # autostart: Jazzy and later) and a method no rclpy has.
    "an instance's method and keyword": (
        "from rclpy.node import Node\n\ndef f(node: Node):\n    node.get_clock().now().to_msg()\n"
        "    node.create_timer(1.0, f, autostart=False)\n    node.get_nodes()\n",
        "<module>:5: rclpy.node.Node.create_timer() has no keyword argument 'autostart' in Humble's rclpy\n"
        "<module>:6: rclpy.node.Node.get_nodes: Humble's rclpy has no such name"),
    # `self` in a subclass: its own names are its own, the rest must be rclpy's (Node.wait_for_node: Iron and
    # later); an attribute it assigns has the type of what it assigns (no rclpy Timer has stop()).
    "self in a subclass": (
        "from rclpy.node import Node\n\nclass Mine(Node):\n    def __init__(self):\n"
        "        super().__init__('mine')\n        self.timer = self.create_timer(1.0, self.tick)\n"
        "        self.timer.cancel()\n        self.timer.stop()\n        self.get_logger().info('x')\n\n"
        "    def tick(self):\n        self.get_clock()\n        self.wait_for_node('other', 1.0)\n",
        "<module>:8: rclpy.timer.Timer.stop: Humble's rclpy has no such name\n"
        "<module>:13: rclpy.node.Node.wait_for_node: Humble's rclpy has no such name"),
    # What Humble has passes: functions of the package through `import rclpy`, with their keywords.
    "what Humble has": ("import rclpy\nrclpy.init(args=None, signal_handler_options=None, domain_id=3)\n"
                        "rclpy.spin(None, executor=None)\n", ""),
}


@pytest.mark.parametrize("case", sorted(LACKING))
def test_the_check_finds_what_humble_lacks(api, case):
    source, expected = LACKING[case]
    assert "\n".join(problems_in(api, source)) == expected
