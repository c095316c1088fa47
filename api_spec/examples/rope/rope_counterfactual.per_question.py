# If the purple cube were much lighter, what would happen?
# expected: B D
# A. The green cube would move up
# B. The purple pulley would not rotate
# C. The pink pulley would move down
# D. The blue pulley would rotate clockwise
# E. The purple pulley would rotate anti-clockwise

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    purple_cube = rope_scene.find("purple cube")

    cf_init_event = rope_scene.register_event(purple_cube, "decrease", "mass")
    rope_cf_scene = rope_scene.init_dyn_simulation(cf_init_event)

    # One check per option: (object, action, target).
    checks = {
        "A": ("green cube", "motion", "up"),
        "B": ("purple pulley", "rotation", "stationary"),
        "C": ("pink pulley", "motion", "down"),
        "D": ("blue pulley", "rotation", "clockwise"),
        "E": ("purple pulley", "rotation", "anti-clockwise"),
    }
    correct = []
    for letter in sorted(checks):
        name, action, target = checks[letter]
        if rope_cf_scene.happen(rope_scene.find(name), action, target):
            correct.append(letter)
    return " ".join(correct)
