# Is the elasticity of the right cloth much less than that of the other?
# expected: yes

def execute_command(video):
    cloth_scene = SoftScene(video, 'cloth')
    right_cloth = cloth_scene.find("right cloth")
    # "The other" cloth is the one on the other side.
    left_cloth = cloth_scene.find("left cloth")

    # Elasticity is how much a cloth stretches.
    right_elasticity, left_elasticity = cloth_scene.query_pair('elasticity', right_cloth, left_cloth)

    return bool_to_yesno(right_elasticity < left_elasticity)
