import impacting_cantilever as ic

# The paper's Figure 4 model with N = 10 modes (k = 100k₁, ζ₁ = 0.01, d₀ = 0, ω = 2(β₁⁻)²):
# the orbit it settles on from rest, by Newton shooting with the exact monodromy matrix.
orbit = ic.find_orbit(ic.problems.figure4(10))
print(orbit)
print("largest multipliers:", orbit.multipliers[:4].round(10))

# The N = 2 orbit continued in k from 100k₁ up to 10⁴k₁ and down to 1k₁, following its
# period doublings to the doubled branches.
result = ic.continue_branch(ic.problems.figure4(2), "stop_stiffness", to=1e4)
for branch in result.branches:
    print(branch)

# A bifurcation diagram: the tip velocity at each impact of each orbit along the branches,
# stable orbits coloured by period, unstable ones light, the period doublings dotted.
try:
    import matplotlib.pyplot as plt
except ImportError:  # the computation above needs no plotting library
    plt = None
if plt is not None:
    fig, ax = plt.subplots(figsize=(7, 3.6))
    for branch in result.branches:
        colour = f"C{branch.period_m.bit_length() - 1}"
        for stable, style in [(False, dict(ms=1, color="0.8")), (True, dict(ms=1.5, color=colour))]:
            points = [(k, v) for k, vs, s in zip(branch.parameter, branch.impact_velocities,
                                                 branch.stable) if s == stable for v in vs]
            if points:
                ax.plot(*zip(*points), ".", **style)
        ax.plot([], [], ".", color=colour, label=f"period {branch.period_m}")
        for b in branch.bifurcations:
            if b.kind == "PeriodDoubling":
                ax.axvline(b.parameter, color="0.5", lw=0.5, ls=":")
    handles, labels = ax.get_legend_handles_labels()
    unique = dict(zip(labels, handles))
    ax.legend(unique.values(), unique.keys(), frameon=False, markerscale=4)
    ax.set(xscale="log", xlabel="stop stiffness k/k₁", ylabel="tip velocity at impact",
           title="N = 2, ζ₁ = 0.01, ω = 2(β₁⁻)², d₀ = 0")
    fig.tight_layout()
    fig.savefig("bifurcation.png", dpi=150)
