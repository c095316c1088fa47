# Which direction would the blue pulley rotate if the purple cube were much lighter?
# expected: B
# A. Stationary
# B. Clockwise
# C. Anti-clockwise

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    purple_cube = rope_scene.find("purple cube")
    blue_pulley = rope_scene.find("blue pulley")

    cf_init_event = rope_scene.register_event(purple_cube, "decrease", "mass")
    rope_cf_scene = rope_scene.init_dyn_simulation(cf_init_event)

    targets = {"A": "stationary", "B": "clockwise", "C": "anti-clockwise"}
    correct = [letter for letter in sorted(targets) if rope_cf_scene.happen(blue_pulley, "rotation", targets[letter])]
    return " ".join(correct)
