# Does the green plate collide with the blue plate? | No
# expected: yes

def execute_command(video):
    cloth_scene = SoftScene(video, 'cloth')
    green_plate = cloth_scene.find("green plate")
    blue_plate = cloth_scene.find("blue plate")

    pred_init_event = cloth_scene.register_event([], "simulate", "")
    cloth_pred_scene = cloth_scene.init_dyn_simulation(pred_init_event)

    # happen takes one object; the other one is the target.
    collided = cloth_pred_scene.happen(green_plate, "collision", blue_plate)
    # The option "No" holds when they do not collide.
    return bool_to_yesno(not collided)
