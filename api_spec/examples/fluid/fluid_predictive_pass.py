# Which stick will the fluid from the other yellow emitter pass? | Gray stick
# expected: yes

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    # "the other yellow emitter" is the yellow fluid's later emitter, opening near the end.
    other_yellow_emitter = fluid_scene.find("other yellow emitter")
    yellow_fluid = fluid_scene.find("yellow fluid")
    gray_stick = fluid_scene.find("gray stick")

    # In the scene where that emitter emits, the yellow fluid is the fluid it pours.
    pred_init_event = fluid_scene.register_event(other_yellow_emitter, "emit", "fluid")
    fluid_pred_scene = fluid_scene.init_dyn_simulation(pred_init_event)

    flag = fluid_pred_scene.happen(yellow_fluid, "passing", gray_stick)
    return bool_to_yesno(flag)
