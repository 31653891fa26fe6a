"""One compilation per problem structure.

`jax.jit` compiles a function once per Python function object. An analysis that
builds its equations as a closure (`F(u, p)` over a scene, its scales, its
period) makes a new function object at every call, so a second branch, grid or
survey of the same rotor, or of another rotor of the same layout, compiles again:
for a small harmonic balance the compilation is most of the wall time.

`lift(fun, *example)` traces `fun` once and returns a `Lifted` function: an
`eqx.Module` whose leaves are the arrays `fun` closed over (those of inner
compiled calls too) and whose static part, the `Structure`, is the traced
program. Two lifted functions whose programs are the same (equation by equation:
primitives, parameters, shapes; literals by value) get the same `Structure`
object, and `compiled(fn)` compiles `fn(lifted, *args)` once per structure: the
same rotor with another stiffness, unbalance or scale reuses it. `call`,
`jacobian` and `vmapped` are such entry points.

What is never shared: a Python number `fun` closes over is a literal of the
program (pass a value that changes from call to call as a JAX array); a Python
object in a parameter (a custom derivative rule, a callback) is compared by
identity, so a program holding one is shared only by lifts that hold the same
object; a custom derivative rule without symbolic zeros (`lax.custom_root`'s) is
compared by its traced program. The structures last seen are kept (`KEPT`), each with its compiled
programs; an older one lives as long as a lifted function holds it."""

import collections
import enum

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.extend.core import ClosedJaxpr, Jaxpr, Literal, jaxpr_as_fun

#: how many structures are kept once no lifted function holds them
KEPT = 64


class Structure:
    """A traced program: the same object for every lift that traced the same
    program (see the module docstring); its compiled entry points live with it."""

    def __init__(self, jaxpr, in_tree, out_tree, key):
        self.jaxpr, self.in_tree, self.out_tree, self.key = jaxpr, in_tree, out_tree, key
        self.compiled = {}


class _Inline(Exception):
    """A compiled inner call holds arrays: trace again with it in line."""


#: parameter values compared by value (a tuple's items one by one)
_PLAIN = (int, float, complex, bool, str, type(None), np.dtype, np.generic, enum.Enum, jax.sharding.Mesh,
          jax.sharding.AbstractMesh, jax.sharding.NamedSharding, jax.sharding.PartitionSpec)


def _fingerprint(jaxpr, in_rule=False):
    """The program as nested tuples: each equation's primitive, parameters and
    variables (numbered in order of appearance, with their shapes and dtypes),
    literals by value, any other object by identity (the program holds it, so the
    identity is not reused while the key exists). Raises `_Inline` at an inner
    compiled call that holds arrays. A derivative rule inside a rule is compared by
    identity (a rule that calls its own function would recurse forever)."""
    names = {}

    def var(v):
        if isinstance(v, Literal):
            return "literal", repr(v.val), v.aval
        if v not in names:
            names[v] = len(names), v.aval
        return names[v]

    def param(p, inline_ok):
        if isinstance(p, ClosedJaxpr):
            if p.consts:
                if inline_ok:
                    raise _Inline
                return "object", id(p)
            return "closed", _fingerprint(p.jaxpr, in_rule)
        if isinstance(p, Jaxpr):
            return "jaxpr", _fingerprint(p, in_rule)
        if isinstance(p, (tuple, list)):
            return type(p).__name__, tuple(param(q, False) for q in p)
        if isinstance(p, _PLAIN) or type(p).__name__ in ("UnspecifiedValue", "ShapedArray", "PyTreeDef"):
            return type(p).__name__, repr(p)
        return "object", id(p)

    def params(e):
        out = []
        for k, v in sorted(e.params.items()):
            if k == "jvp_jaxpr_fun" and e.params.get("symbolic_zeros") is False and not in_rule:
                # a custom derivative rule (lax.custom_root's implicit function theorem): by its
                # program, traced with every tangent given (without symbolic zeros, the rule
                # always sees them all)
                rule, consts, zeros = v.call_wrapped(*[False] * (len(e.invars) - e.params["num_consts"]))
                out.append((k, ("rule", _fingerprint(rule, True), tuple(id(c) for c in consts), tuple(zeros))))
            else:
                out.append((k, param(v, e.primitive.name in ("jit", "pjit"))))
        return tuple(out)

    head = (tuple(map(var, jaxpr.constvars)), tuple(map(var, jaxpr.invars)))
    eqns = tuple((e.primitive.name, params(e), tuple(map(var, e.invars)), tuple(map(var, e.outvars)))
                 for e in jaxpr.eqns)
    return head, eqns, tuple(map(var, jaxpr.outvars))


#: the structures last seen, by key
_SEEN = collections.OrderedDict()


def _canonical(jaxpr, in_tree, out_tree):
    key = (_fingerprint(jaxpr), in_tree, out_tree)
    s = _SEEN.pop(key, None) or Structure(jaxpr, in_tree, out_tree, key)
    _SEEN[key] = s
    while len(_SEEN) > KEPT:
        _SEEN.popitem(last=False)
    return s


class Lifted(eqx.Module):
    """`fun` with its closed-over arrays as leaves (see the module docstring);
    called with arguments of the example's structure, shapes and dtypes."""

    structure: Structure = eqx.field(static=True)
    consts: tuple

    def __call__(self, *args):
        leaves, tree = jax.tree_util.tree_flatten(args)
        if tree != self.structure.in_tree:
            raise TypeError(f"lifted function called with {tree}, traced with {self.structure.in_tree}")
        out = jaxpr_as_fun(ClosedJaxpr(self.structure.jaxpr, list(self.consts)))(*leaves)
        return jax.tree_util.tree_unflatten(self.structure.out_tree, out)


def lift(fun, *example) -> Lifted:
    """`fun` traced at `example` (arrays, or pytrees of arrays) as a `Lifted`
    function."""
    leaves, in_tree = jax.tree_util.tree_flatten(example)
    out = []

    def flat(*xs):
        out_leaves, out_tree = jax.tree_util.tree_flatten(fun(*jax.tree_util.tree_unflatten(in_tree, xs)))
        out.append(out_tree)
        return out_leaves

    closed = jax.make_jaxpr(flat)(*leaves)
    try:
        structure = _canonical(closed.jaxpr, in_tree, out[0])
    except _Inline:   # the arrays of an inner compiled call (a jitted assembly) are made arguments too
        closed = jax.make_jaxpr(lambda *xs: _inlined(closed.jaxpr, closed.consts, *xs))(*leaves)
        structure = _canonical(closed.jaxpr, in_tree, out[0])
    return Lifted(structure, tuple(jnp.asarray(c) for c in closed.consts))


def _inlined(jaxpr, consts, *args):
    """`jaxpr` evaluated with every inner compiled call (`jit`) evaluated in line:
    traced, the arrays those calls closed over become the outer program's constants."""
    env = dict(zip(jaxpr.constvars, consts))
    env.update(zip(jaxpr.invars, args))

    def read(v):
        return v.val if isinstance(v, Literal) else env[v]

    for eqn in jaxpr.eqns:
        ins = [read(v) for v in eqn.invars]
        inner = eqn.params.get("jaxpr") if eqn.primitive.name in ("jit", "pjit") else None
        if isinstance(inner, ClosedJaxpr):
            outs = _inlined(inner.jaxpr, inner.consts, *ins)
        else:
            outs = eqn.primitive.bind(*ins, **eqn.primitive.get_bind_params(eqn.params))
            outs = outs if eqn.primitive.multiple_results else [outs]
        env.update(zip(eqn.outvars, outs))
    return [read(v) for v in jaxpr.outvars]


def compiled(fn):
    """`fn(f, *args)` (`f` a `Lifted` function, `args` arrays or pytrees of
    arrays), compiled once per structure of `f` and kept with it."""
    def run(f, *args):
        s = f.structure
        jf = s.compiled.get(fn)
        if jf is None:
            def lifted(consts, *a):
                return fn(Lifted(s, consts), *a)

            lifted.__name__ = lifted.__qualname__ = fn.__name__   # compile logs name the function
            jf = s.compiled[fn] = jax.jit(lifted)
        return jf(f.consts, *args)

    run.__doc__ = fn.__doc__
    return run


@compiled
def call(f, *args):
    """`f(*args)`, compiled once per structure of `f` (a `Lifted` function)."""
    return f(*args)


@compiled
def jacobian(f, x, *args):
    """`jax.jacfwd(f)(x, *args)`, compiled once per structure of `f`."""
    return jax.jacfwd(f)(x, *args)


@compiled
def vmapped(f, *args):
    """`jax.vmap(f)(*args)` (every argument batched on its first axis), compiled
    once per structure of `f`."""
    return jax.vmap(f)(*args)


#: rows per call of `batched`, at most
ROWS = 64


def batched(fn, f, rows, *fixed, row_bytes=0):
    """`fn(f, *chunk, *fixed)` (a `compiled` function, batched over its row
    arguments) over chunks of `ROWS` rows of the arrays `rows` (fewer, a power of
    two, where each row's output takes `row_bytes`: a chunk's within 256 MiB), the
    last chunk padded with copies of the first row (one compilation whatever the
    number of rows); the outputs (a tuple of arrays) joined row by row, as NumPy
    arrays."""
    outs = [o for _, o in chunks(fn, f, rows, *fixed, row_bytes=row_bytes)]
    return tuple(np.concatenate([o[j] for o in outs]) for j in range(len(outs[0])))


def chunks(fn, f, rows, *fixed, row_bytes=0):
    """`batched`'s chunks one at a time, for outputs too large to hold for every row
    at once: yields `(first, outputs)`, `first` the index of the chunk's first row,
    `outputs` its rows' (NumPy arrays, the padding cut)."""
    k = rows[0].shape[0]
    size = ROWS
    while size > 1 and size * row_bytes > 2 ** 28:
        size //= 2
    pad = np.concatenate([np.arange(k), np.zeros(-k % size, dtype=int)])
    for i in range(0, pad.size, size):
        out = fn(f, *(jnp.asarray(np.asarray(a)[pad[i:i + size]]) for a in rows), *fixed)
        yield i, tuple(np.asarray(o)[:max(min(size, k - i), 0)] for o in out)
