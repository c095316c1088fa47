# Which container will fluid from the other yellow emitter flow into? | Green container
# expected: yes

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    other_yellow_emitter = fluid_scene.find("other yellow emitter")
    yellow_fluid = fluid_scene.find("yellow fluid")
    green_container = fluid_scene.find("green container")

    pred_init_event = fluid_scene.register_event(other_yellow_emitter, "emit", "fluid")
    fluid_pred_scene = fluid_scene.init_dyn_simulation(pred_init_event)

    flag = fluid_pred_scene.happen(yellow_fluid, "entering", green_container)
    return bool_to_yesno(flag)
