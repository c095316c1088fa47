# If the brown stick were removed, which stick would pink fluid pass?
# expected: A
# A. Cyan stick
# B. Gray stick

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    pink_fluid = fluid_scene.find("pink fluid")

    cf_init_event = fluid_scene.register_event([], "remove", "brown stick")
    fluid_cf_scene = fluid_scene.init_dyn_simulation(cf_init_event)

    options = {"A": "cyan stick", "B": "gray stick"}
    correct = []
    for letter in sorted(options):
        if fluid_cf_scene.happen(pink_fluid, "passing", fluid_scene.find(options[letter])):
            correct.append(letter)
    return " ".join(correct)
