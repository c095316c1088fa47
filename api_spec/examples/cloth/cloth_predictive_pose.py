# Which phrase below can best describe the final pose of the gray pillar? | It leans at an angle, its top still pointing up
# expected: yes

def execute_command(video):
    cloth_scene = SoftScene(video, 'cloth')
    gray_pillar = cloth_scene.find("gray pillar")

    pred_init_event = cloth_scene.register_event([], "simulate", "")
    cloth_pred_scene = cloth_scene.init_dyn_simulation(pred_init_event)

    # final_pose returns the phrase of the pose, spelled as the options spell it.
    pose = cloth_pred_scene.final_pose(gray_pillar)
    return bool_to_yesno(pose == "It leans at an angle, its top still pointing up")
