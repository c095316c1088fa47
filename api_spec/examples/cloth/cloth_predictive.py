# Is the blue pillar finally in touch with the yellow plate?
# runnable: no (the paper's listing eg3; cloth scenes have no backend in this version)

def execute_command(video):
    cloth_scene = SoftScene(video, 'cloth')
    blue_pillar = cloth_scene.find("blue pillar")
    yellow_plate = cloth_scene.find("yellow plate")

    pred_init_event = cloth_scene.register_event([], "simulate", "")
    cloth_pred_scene = cloth_scene.init_dyn_simulation(pred_init_event)

    # happen takes one object; the other one is the target.
    flag = cloth_pred_scene.happen([blue_pillar], "touching", [yellow_plate])

    return bool_to_yesno(flag)
