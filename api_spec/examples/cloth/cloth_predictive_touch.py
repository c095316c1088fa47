# Is the green plate finally in touch with the gray pillar? | Yes
# expected: yes

def execute_command(video):
    cloth_scene = SoftScene(video, 'cloth')
    green_plate = cloth_scene.find("green plate")
    gray_pillar = cloth_scene.find("gray pillar")

    pred_init_event = cloth_scene.register_event([], "simulate", "")
    cloth_pred_scene = cloth_scene.init_dyn_simulation(pred_init_event)

    # happen takes one object; the other one is the target.
    flag = cloth_pred_scene.happen([green_plate], "touching", [gray_pillar])
    return bool_to_yesno(flag)
