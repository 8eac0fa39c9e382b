"""The resolved structure of a project, as plain data (JSON) and as a rich tree."""

from __future__ import annotations

from typing import Any

from rich.tree import Tree

from tockbmc.model import ast
from tockbmc.report.pretty import expr_text, stmt_text, trigger_text

Data = dict[str, Any]


def _pos(p: ast.Pos) -> str:
    return f"{p.path}:{p.line}:{p.column}"


def _event(e: ast.Event) -> Data:
    return {"name": e.name, "type": str(e.type) if e.type is not None else None}


def _variable(v: ast.Variable) -> Data:
    return {"name": v.name, "type": str(v.type), "constant": v.constant,
            "initial": expr_text(v.initial) if v.initial is not None else None}


def _operation_sig(o: ast.OperationSig) -> Data:
    return {"name": o.name, "parameters": [{"name": p.name, "type": str(p.type)} for p in o.parameters]}


def _nodes_data(b: ast.Behaviour) -> list[Data]:
    """The top-level nodes of `b`, each with its children under "nodes" (a loop: states may nest deeply)."""
    by_path: dict[str, Data] = {}
    for n in b.nodes:
        data: Data = {"name": n.name, "kind": "probabilistic" if n.probabilistic else n.kind, "path": n.path,
                      "pos": _pos(n.pos)}
        for kind in ("entry", "during", "exit"):
            action = getattr(n, kind)
            if action is not None:
                data[kind] = stmt_text(action)
        by_path[n.path] = data
    for n in b.nodes:
        if n.children:
            by_path[n.path]["nodes"] = [by_path[c] for c in n.children]
    return [by_path[n.path] for n in b.nodes if n.parent is None]


def _transition(t: ast.Transition) -> Data:
    return {
        "name": t.name, "from": t.source, "to": t.target, "pos": _pos(t.pos),
        "trigger": trigger_text(t.trigger) if t.trigger else None,
        "clock_resets": [c.name for c in t.clock_resets],
        "deadline": expr_text(t.deadline) if t.deadline is not None else None,
        "condition": "else" if t.is_else else (expr_text(t.condition) if t.condition is not None else None),
        "action": stmt_text(t.action) if t.action is not None else None,
    }


def behaviour_data(b: ast.Behaviour) -> Data:
    data: Data = {
        "name": b.name, "qname": b.qname, "pos": _pos(b.pos),
        "events": [_event(e) for e in b.events],
        "variables": [_variable(v) for v in b.variables],
        "interface_variables": [_variable(v) for v in b.interface_variables],
        "clocks": [c.name for c in b.clocks],
        "operations": [_operation_sig(o) for o in b.operations],
        "nodes": _nodes_data(b),
        "transitions": [_transition(t) for t in b.transitions],
    }
    if isinstance(b, ast.OperationDef):
        data["parameters"] = [{"name": p.name, "type": str(p.type)} for p in b.parameters]
    return data


def _connection(c: ast.Connection) -> Data:
    return {"from": c.source, "from_event": c.source_event.name, "to": c.target, "to_event": c.target_event.name,
            "async": c.asynchronous, "mult": c.bidirectional}


def controller_data(c: ast.Controller) -> Data:
    return {
        "name": c.name, "qname": c.qname, "pos": _pos(c.pos),
        "events": [_event(e) for e in c.events],
        "variables": [_variable(v) for v in c.variables],
        "machines": [{"instance": m.name, **behaviour_data(m.machine)} for m in c.machines],
        "operations": [{"instance": o.name, **behaviour_data(o.operation)} for o in c.operations],
        "connections": [_connection(x) for x in c.connections],
    }


def module_data(m: ast.Module) -> Data:
    platform = None
    if m.platform is not None:
        platform = {"name": m.platform_name, "definition": m.platform.qname,
                    "events": [_event(e) for e in m.platform.events],
                    "variables": [_variable(v) for v in m.platform.variables],
                    "operations": [_operation_sig(o) for o in m.platform.operations]}
    return {"name": m.name, "qname": m.qname, "pos": _pos(m.pos), "platform": platform,
            "controllers": [{"instance": c.name, **controller_data(c.controller)} for c in m.controllers],
            "connections": [_connection(x) for x in m.connections]}


def _type(t: ast.Type) -> Data:
    data: Data = {"name": t.name}
    if isinstance(t, ast.RecordType):
        data.update(kind="record", fields=[{"name": f.name, "type": str(f.type)} for f in t.fields])
    elif isinstance(t, ast.EnumType):
        data.update(kind="enumeration", literals=list(t.literals))
        if t.params:
            data["parameters"] = {lit: [str(pt) for pt in ps] for lit, ps in zip(t.literals, t.params, strict=True) if ps}
    else:
        data.update(kind="type")
    return data


def project_data(project: ast.Project) -> Data:
    """Everything `tockbmc show --format json` prints."""
    return {
        "files": list(project.files),
        "types": [_type(t) for t in project.types],
        "interfaces": [{"name": i.qname, "events": [_event(e) for e in i.events],
                        "variables": [_variable(v) for v in i.variables],
                        "operations": [_operation_sig(o) for o in i.operations]} for i in project.interfaces],
        "functions": [{"name": f.qname, "parameters": [{"name": p.name, "type": str(p.type)} for p in f.parameters],
                       "result": str(f.result),
                       "definition": expr_text(f.definition) if f.definition is not None else None}
                      for f in project.functions],
        "modules": [module_data(m) for m in project.modules],
        "controllers": [controller_data(c) for c in project.controllers],
        "machines": [behaviour_data(m) for m in project.machines],
        "operations": [behaviour_data(o) for o in project.operations],
        "csp_blocks": [{"name": b.name, "timing": b.timing, "defines": list(b.defines), "pos": _pos(b.pos)}
                       for b in project.csp_blocks],
        "assertions": [{"name": a.label, "kind": a.kind, "negated": a.negated, "subject": a.subject,
                        "other": a.other, "model": a.semantic_model, "timing": a.timing, "text": a.text,
                        "pos": _pos(a.pos)} for a in project.assertions],
    }


# ----------------------------------------------------------------------------- the tree


def _decls(tree: Tree, data: Data) -> None:
    if data.get("events"):
        tree.add("[bold]events[/] " + ", ".join(
            e["name"] + (f" : {e['type']}" if e["type"] else "") for e in data["events"]))
    if data.get("operations") and not isinstance(data["operations"][0].get("nodes"), list):
        tree.add("[bold]operations[/] " + ", ".join(
            f"{o['name']}({', '.join(p['name'] + ' : ' + p['type'] for p in o['parameters'])})"
            for o in data["operations"]))
    variables = data.get("variables", []) + data.get("interface_variables", [])
    if variables:
        tree.add("[bold]variables[/] " + ", ".join(
            ("const " if v["constant"] else "var ") + f"{v['name']} : {v['type']}"
            + (f" = {v['initial']}" if v["initial"] else "") for v in variables))
    if data.get("clocks"):
        tree.add("[bold]clocks[/] " + ", ".join(data["clocks"]))


def _nodes(tree: Tree, nodes: list[Data]) -> None:
    todo = [(tree, n) for n in reversed(nodes)]
    while todo:  # depth first, in order, without recursion
        parent, n = todo.pop()
        branch = parent.add(f"[cyan]{n['kind']}[/] {n['name']}")
        for kind in ("entry", "during", "exit"):
            if kind in n:
                branch.add(f"{kind} {_escape(n[kind])}")
        todo.extend((branch, c) for c in reversed(n.get("nodes", [])))


def _escape(text: str) -> str:
    return text.replace("[", "\\[")


def _behaviour_tree(parent: Tree, label: str, data: Data) -> None:
    node = parent.add(label)
    _decls(node, data)
    if data["nodes"]:
        _nodes(node.add("[bold]nodes[/]"), data["nodes"])
    if data["transitions"]:
        ts = node.add("[bold]transitions[/]")
        for t in data["transitions"]:
            text = f"{t['name']}: {t['from']} → {t['to']}"
            extra = []
            if t["trigger"]:
                extra.append(f"trigger {t['trigger']}")
            if t["clock_resets"]:
                extra.append(" ".join("#" + c for c in t["clock_resets"]))
            if t["deadline"]:
                extra.append(f"<{{{t['deadline']}}}")
            if t["condition"]:
                extra.append(f"condition {t['condition']}")
            if t["action"]:
                extra.append(f"action {t['action']}")
            ts.add(_escape(text + ("  " + "  ".join(extra) if extra else "")))


def _controller_tree(parent: Tree, label: str, data: Data) -> None:
    node = parent.add(label)
    _decls(node, data)
    for m in data["machines"]:
        _behaviour_tree(node, f"[green]stm[/] {m['instance']}" + (f" = {m['qname']}" if m["instance"] != m["name"] else ""), m)
    for o in data["operations"]:
        _behaviour_tree(node, f"[green]operation[/] {o['instance']} = {o['qname']}", o)
    _connections(node, data["connections"])


def _connections(parent: Tree, connections: list[Data]) -> None:
    if connections:
        cs = parent.add("[bold]connections[/]")
        for c in connections:
            cs.add(f"{c['from']}.{c['from_event']} → {c['to']}.{c['to_event']}"
                   + (" (async)" if c["async"] else ""))


def project_tree(project: ast.Project) -> Tree:
    """The tree `tockbmc show` prints: modules down to states, then the rest."""
    data = project_data(project)
    root = Tree(f"[bold]project[/] {project.root}")
    used_controllers = {c["qname"] for m in data["modules"] for c in m["controllers"]}
    used_machines = {m["qname"] for c in data["controllers"] for m in c["machines"]}
    used_machines |= {m["qname"] for mod in data["modules"] for c in mod["controllers"] for m in c["machines"]}
    for m in data["modules"]:
        node = root.add(f"[magenta]module[/] {m['name']}")
        if m["platform"]:
            p = m["platform"]
            _decls(node.add(f"[magenta]robotic platform[/] {p['name']}"), p)
        for c in m["controllers"]:
            _controller_tree(node, f"[blue]controller[/] {c['instance']}"
                             + (f" = {c['qname']}" if c["instance"] != c["name"] else ""), c)
        _connections(node, m["connections"])
    for c in data["controllers"]:
        if c["qname"] not in used_controllers:
            _controller_tree(root, f"[blue]controller[/] {c['qname']}", c)
    for m in data["machines"]:
        if m["qname"] not in used_machines:
            _behaviour_tree(root, f"[green]stm[/] {m['qname']}", m)
    if data["assertions"]:
        a_node = root.add("[bold]assertions[/]")
        for a in data["assertions"]:
            a_node.add(_escape(f"{a['name']}: {a['text']}"))
    return root
