# Which phrase below can best describe the final pose of the gray pillar?
# expected: A
# A. It leans at an angle, its top still pointing up
# B. It is tilted upside down at an angle, its top pointing down
# C. It stands upside down on its top
# D. It stands upright
# E. It lies flat on its back, front or side

def execute_command(video):
    cloth_scene = SoftScene(video, 'cloth')
    gray_pillar = cloth_scene.find("gray pillar")

    pred_init_event = cloth_scene.register_event([], "simulate", "")
    cloth_pred_scene = cloth_scene.init_dyn_simulation(pred_init_event)

    pose = cloth_pred_scene.final_pose(gray_pillar)
    options = {
        "A": "It leans at an angle, its top still pointing up",
        "B": "It is tilted upside down at an angle, its top pointing down",
        "C": "It stands upside down on its top",
        "D": "It stands upright",
        "E": "It lies flat on its back, front or side",
    }
    correct = [letter for letter, phrase in options.items() if phrase == pose]
    return " ".join(correct)
