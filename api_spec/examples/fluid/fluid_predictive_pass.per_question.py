# Which stick will the fluid from the other yellow emitter pass?
# expected: B C
# A. Brown stick
# B. Cyan stick
# C. Gray stick

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    other_yellow_emitter = fluid_scene.find("other yellow emitter")
    yellow_fluid = fluid_scene.find("yellow fluid")

    pred_init_event = fluid_scene.register_event(other_yellow_emitter, "emit", "fluid")
    fluid_pred_scene = fluid_scene.init_dyn_simulation(pred_init_event)

    # Each option is a stick; every stick the fluid passes is an answer.
    options = {"A": "brown stick", "B": "cyan stick", "C": "gray stick"}
    correct = []
    for letter in sorted(options):
        if fluid_pred_scene.happen(yellow_fluid, "passing", fluid_scene.find(options[letter])):
            correct.append(letter)
    return " ".join(correct)
