# What can we do to let the green cube to move up?
# expected: A B
# A. Decrease the mass of the green cube
# B. Increase the mass of the purple cube
# C. Decrease the mass of the pink sphere
# D. Increase the mass of the green cube

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    green_cube = rope_scene.find("green cube")

    # Each option is an event: (load, action). The goal must happen in the scene it starts.
    options = {
        "A": ("green cube", "decrease"),
        "B": ("purple cube", "increase"),
        "C": ("pink sphere", "decrease"),
        "D": ("green cube", "increase"),
    }
    correct = []
    for letter in sorted(options):
        load, action = options[letter]
        gd_init_event = rope_scene.register_event(rope_scene.find(load), action, "mass")
        rope_gd_scene = rope_scene.init_dyn_simulation(gd_init_event)
        if rope_gd_scene.happen(green_cube, "motion", "up"):
            correct.append(letter)
    return " ".join(correct)
