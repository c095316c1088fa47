# What can we do to let most of the light blue fluid enter the red container?
# expected: B
# A. Remove the brown stick
# B. Remove the gray stick

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    light_blue_fluid = fluid_scene.find("light blue fluid")
    red_container = fluid_scene.find("red container")

    # Each option is an event (a stick to remove). The goal must happen in the scene it starts.
    options = {"A": "brown stick", "B": "gray stick"}
    correct = []
    for letter in sorted(options):
        gd_init_event = fluid_scene.register_event([], "remove", options[letter])
        fluid_gd_scene = fluid_scene.init_dyn_simulation(gd_init_event)
        if fluid_gd_scene.happen(light_blue_fluid, "entering most", red_container):
            correct.append(letter)
    return " ".join(correct)
