# Does the green plate fall over? | Yes
# expected: yes

def execute_command(video):
    cloth_scene = SoftScene(video, 'cloth')
    green_plate = cloth_scene.find("green plate")

    # The cloth hides the boxes: predict what happens under it in the video's future.
    pred_init_event = cloth_scene.register_event([], "simulate", "")
    cloth_pred_scene = cloth_scene.init_dyn_simulation(pred_init_event)

    flag = cloth_pred_scene.happen(green_plate, "falling", "")
    return bool_to_yesno(flag)
