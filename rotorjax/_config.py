"""Float64 for the whole package.

rotorjax enables JAX's 64-bit mode when it is imported (`jax_enable_x64`), because
the stability margins and balanced states it computes are below single precision.
Import rotorjax before creating any JAX arrays you will pass to it, or set the
environment variable `JAX_ENABLE_X64=1` yourself.
"""

import jax

jax.config.update("jax_enable_x64", True)
